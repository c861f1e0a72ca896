// The wave packets of points.las (formats 9, 10; physics.waveform.keep), beside the LAS sink's
// records: each pulse with points gets one packet, which all its returns share.
//
// Encoding (docs/formats.md): 32 bits per sample, compression 0, digitiser offset 0 and gain
// g = detection threshold / 64 (peak power / (2^32 - 1) when the threshold is 0): a sample of w
// watts is stored as round(w / g), clamped to [0, 2^32 - 1], so it reads back within g / 2
// (1/128 of the threshold) up to 6.7e7 times the threshold (a digitiser's saturation beyond).
// Packets have a fixed size per descriptor: descriptor i (1-22) holds 2^(i+2) samples (8 to
// 16.7 M); a pulse's samples fill the smallest that holds them, zeros after (the waveform is zero
// there). The temporal spacing is bin_ns in whole picoseconds. Every value depends only on the
// pulse, so the files are the same at any thread count.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/io/las_wave_packets.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/point_sink.hpp"

namespace beamtrace::detail {

/// Descriptors 1-22 of the encoding above.
[[nodiscard]] std::vector<LasWavePacketDescriptor> wave_packet_descriptors(
    const WaveformFacts& facts);

class WavePacketStream {
  public:
    /// Opens points.wdp (storage external) or a staging file (internal) beside `las_path`.
    WavePacketStream(const std::filesystem::path& las_path, const WaveformFacts& facts);

    /// The descriptor VLRs for the writer's config.
    [[nodiscard]] std::vector<LasVlr> vlrs() const;
    /// Encodes the block's points into `records` and their packets into `packets`; the records'
    /// offsets are relative to the block's first packet until write(). Thread-safe.
    void encode(const PointBlock& block, const LasWriter& writer, LasRecordBlock& records,
                std::string& packets) const;
    /// Completes the records' offsets and appends the packets; blocks in order, one thread.
    void write(const LasWriter& writer, LasRecordBlock& records, const std::string& packets);
    /// Closes `writer` (copying the staged packets into its EVLR) and commits points.wdp.
    [[nodiscard]] std::vector<std::filesystem::path> commit(LasWriter& writer);
    void abort() noexcept { file_.reset(); }

  private:
    WaveformFacts facts_;
    std::vector<LasWavePacketDescriptor> descriptors_;
    std::unique_ptr<AtomicFile> file_;  ///< points.wdp, or the staging file (never committed)
    std::uint64_t base_ = kLasEvlrHeaderBytes;  ///< offset of the next block's first packet
};

}  // namespace beamtrace::detail
