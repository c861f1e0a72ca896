// Several scanners on one platform (a survey's `scanners:` list, docs/survey.md "Several
// scanners"): ScannerSet merges the pulses of its scanners' patterns into one ScanPattern.
//
// Order: the pulses of all scanners sorted by emission time, equal times by scanner index (then
// by the scanner's own pulse order). Pulse i of the set is therefore the pulse of rank i in that
// order, a function of the scanners' pulse_time_s() alone: the same for any chunking or thread
// count, and two scanners firing in step interleave 0, 1, 0, 1, ... Each pulse carries its
// scanner's index in PulseBatch::scanner; its time, direction (in ITS scanner's frame), channel
// and scan angle are those of its scanner's pattern bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

class ScannerSet final : public ScanPattern {
  public:
    /// Throws ConfigError when `scanners` is empty, holds more than 255 patterns or a null one.
    explicit ScannerSet(std::vector<std::unique_ptr<ScanPattern>> scanners);

    /// The sum of the scanners' pulse counts.
    [[nodiscard]] std::uint64_t pulse_count() const override { return total_; }
    /// The mean rate: pulse_count() / (end_time_s() - start_time_s()) (0 without pulses).
    [[nodiscard]] double pulse_rate_hz() const override;
    /// The earliest start among the scanners with pulses (the first scanner's without any).
    [[nodiscard]] double start_time_s() const override;
    /// The time of the pulse of rank i (i = pulse_count(): end_time_s()).
    [[nodiscard]] double pulse_time_s(std::uint64_t i) const override;
    /// The latest end among the scanners with pulses (the first scanner's start without any).
    [[nodiscard]] double end_time_s() const override;

    [[nodiscard]] std::size_t scanner_count() const { return scanners_.size(); }
    [[nodiscard]] const ScanPattern& scanner(std::size_t s) const { return *scanners_.at(s); }
    /// For each scanner, how many of its pulses are among the first `g` pulses of the set
    /// (g <= pulse_count()); the counts add up to g.
    [[nodiscard]] std::vector<std::uint64_t> split(std::uint64_t g) const;

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;
    /// The rank of scanner s's pulse i in the set's order.
    [[nodiscard]] std::uint64_t rank(std::size_t s, std::uint64_t i) const;

    std::vector<std::unique_ptr<ScanPattern>> scanners_;
    std::uint64_t total_ = 0;
};

}  // namespace beamtrace
