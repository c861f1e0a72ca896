// The sinks of one run, driven together: encode a block for all (pool or writer thread), write it
// to all (writer thread, block order), commit all; a failure anywhere, or destruction before
// commit(), aborts all, so no output is left half-written.
#pragma once

#include <algorithm>

#include <filesystem>
#include <memory>
#include <vector>

#include "beamtrace/io/point_sink.hpp"

namespace beamtrace::detail {

/// One block's encoded output for every sink of a SinkSet (a slot of the ordered window).
struct BlockOutput {
    std::vector<std::unique_ptr<SinkBuffer>> sinks;  ///< one per sink, made on first use
    std::size_t points = 0;                          ///< points in the block
    std::size_t weather_points = 0;  ///< of which the weather's (BlockPoint::weather)
    /// The block's points while they wait for the writer thread to encode them (a survey's
    /// BlockWriter::own_thread); empty otherwise.
    PointBlock pending;
    bool deferred = false;  ///< true when `pending` holds the block's points, to encode
    void clear() {
        deferred = false;
        for (auto& s : sinks) {
            s->clear();
        }
        points = 0;
        weather_points = 0;
    }
};

class SinkSet {
  public:
    SinkSet() = default;
    explicit SinkSet(std::vector<std::unique_ptr<PointSink>> sinks) : sinks_(std::move(sinks)) {}
    ~SinkSet() { abort(); }
    SinkSet(const SinkSet&) = delete;
    SinkSet& operator=(const SinkSet&) = delete;
    SinkSet(SinkSet&&) = default;
    SinkSet& operator=(SinkSet&&) = delete;

    void add(std::unique_ptr<PointSink> sink) { sinks_.push_back(std::move(sink)); }
    [[nodiscard]] std::size_t size() const { return sinks_.size(); }

    /// Encodes `block` for every sink into `out` (its buffers made on first use). Thread-safe.
    void encode(const PointBlock& block, BlockOutput& out) const {
        if (out.sinks.size() != sinks_.size()) {
            out.sinks.clear();
            for (const auto& s : sinks_) {
                out.sinks.push_back(s->make_buffer());
            }
        }
        for (std::size_t i = 0; i < sinks_.size(); ++i) {
            sinks_[i]->encode(block, *out.sinks[i]);
        }
        out.points = block.points.size();
        out.weather_points = static_cast<std::size_t>(
            std::count_if(block.points.begin(), block.points.end(),
                          [](const BlockPoint& p) { return p.weather != 0; }));
    }
    /// Writes an encoded block to every sink; one thread, blocks in order.
    void write(const BlockOutput& out) {
        for (std::size_t i = 0; i < sinks_.size(); ++i) {
            sinks_[i]->write(*out.sinks[i]);
        }
    }
    /// Commits every sink in order; returns their files. If one fails, the others are aborted
    /// and the files already committed removed, and the error is rethrown.
    [[nodiscard]] std::vector<std::filesystem::path> commit();
    /// Aborts every sink not yet committed.
    void abort() noexcept;
    /// After commit(): the sinks' notes for the summary, in sink order.
    [[nodiscard]] const std::vector<std::string>& notes() const { return notes_; }

  private:
    std::vector<std::unique_ptr<PointSink>> sinks_;
    std::vector<std::string> notes_;
};

}  // namespace beamtrace::detail
