// A survey of legs (as in HELIOS++): each leg is a time window of the platform's path with its
// own scanner settings, or with the scanner off (no pulse in its window, e.g. on a turn).
//
// LegSequence joins the legs' patterns into one ScanPattern: global pulse i is pulse i - f_l of
// leg l, where f_l is the number of pulses of the legs before l (an inactive leg has none).
// Each active leg's pattern fires from its leg's start time for its leg's duration at its own
// rate (its mirror, head or prisms starting at phase 0 at the leg's start), so pulse times are
// uniform within a leg only: pulse_time_s() and end_time_s() are the legs'. Pulses, channels
// and scan angles are those of the leg's own pattern bit for bit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

/// One leg of a LegSequence.
struct SequenceLeg {
    double start_time_s = 0.0;  ///< the leg's window [start_time_s, end_time_s)
    double end_time_s = 0.0;
    /// The leg's pulses (firing within the window); nullptr: the scanner is off on this leg.
    std::unique_ptr<ScanPattern> pattern;
};

class LegSequence final : public ScanPattern {
  public:
    /// Throws ConfigError when `legs` is empty, a window is not finite and increasing, windows
    /// overlap or are out of order, or a leg's pattern fires outside its window.
    explicit LegSequence(std::vector<SequenceLeg> legs);

    [[nodiscard]] std::uint64_t pulse_count() const override { return first_pulse_.back(); }
    /// The mean rate: pulse_count() / (end_time_s() - start_time_s()) (0 without pulses).
    [[nodiscard]] double pulse_rate_hz() const override;
    /// The first active leg's pattern's start (the first leg's start when none is active).
    [[nodiscard]] double start_time_s() const override;
    /// Pulse i's time: its leg's pattern's pulse_time_s(i - f_l); i = pulse_count(): the end.
    [[nodiscard]] double pulse_time_s(std::uint64_t i) const override;
    /// The last active leg's pattern's end (the first leg's start when none is active).
    [[nodiscard]] double end_time_s() const override;

    [[nodiscard]] std::size_t leg_count() const { return legs_.size(); }
    [[nodiscard]] const SequenceLeg& leg(std::size_t l) const { return legs_.at(l); }
    /// The first global pulse of leg l (l = leg_count(): pulse_count()).
    [[nodiscard]] std::uint64_t first_pulse(std::size_t l) const { return first_pulse_.at(l); }
    /// The leg that fires pulse i (i < pulse_count()).
    [[nodiscard]] std::size_t leg_of(std::uint64_t i) const;
    /// first_pulse(0 .. leg_count()): the table behind leg_of.
    [[nodiscard]] const std::vector<std::uint64_t>& first_pulses() const { return first_pulse_; }

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;

    std::vector<SequenceLeg> legs_;
    std::vector<std::uint64_t> first_pulse_;  ///< size legs_.size() + 1
    std::optional<std::size_t> first_active_, last_active_;
};

/// The leg of pulse `i` in a first-pulse table (LegSequence::first_pulses()): the last l with
/// first_pulses[l] <= i, skipping legs without pulses.
[[nodiscard]] std::size_t leg_of_pulse(const std::vector<std::uint64_t>& first_pulses,
                                       std::uint64_t i);

}  // namespace beamtrace
