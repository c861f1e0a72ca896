#include "io/sinks/wave_packet_stream.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "beamtrace/core/error.hpp"
#include "beamtrace/physics/waveform.hpp"

namespace beamtrace::detail {

namespace {

constexpr int kDescriptors = 22;          ///< 2^3 .. 2^24 samples
constexpr double kRawMax = 4294967295.0;  ///< 2^32 - 1

[[nodiscard]] double gain_of(const WaveformFacts& f) {
    return f.detection_threshold_w > 0 ? f.detection_threshold_w / 64.0 : f.peak_power_w / kRawMax;
}

/// The smallest descriptor index whose packets hold `count` samples (0: none do).
[[nodiscard]] int descriptor_for(std::uint32_t count) {
    const int bits = std::bit_width(std::max<std::uint32_t>(count, 8) - 1);  // 2^bits >= count
    return bits - 2 <= kDescriptors ? bits - 2 : 0;
}

void append_packet(const float* samples, std::uint32_t count, std::uint32_t slots, double gain,
                   std::string& out) {
    const std::size_t at = out.size();
    out.resize(at + 4 * std::size_t{slots}, '\0');
    for (std::uint32_t k = 0; k < count; ++k) {
        const double v = static_cast<double>(samples[k]) / gain;
        const std::uint32_t raw =
            !(v > 0) ? 0u : (v >= kRawMax ? 0xffffffffu : static_cast<std::uint32_t>(v + 0.5));
        std::memcpy(out.data() + at + 4 * std::size_t{k}, &raw, 4);
    }
}

}  // namespace

std::vector<LasWavePacketDescriptor> wave_packet_descriptors(const WaveformFacts& facts) {
    std::vector<LasWavePacketDescriptor> out;
    for (int i = 1; i <= kDescriptors; ++i) {
        LasWavePacketDescriptor d;
        d.index = i;
        d.bits_per_sample = 32;
        d.samples = std::uint32_t{1} << (i + 2);
        d.spacing_ps = static_cast<std::uint32_t>(std::lround(facts.bin_ns * 1000.0));
        d.gain = gain_of(facts);
        out.push_back(d);
    }
    return out;
}

WavePacketStream::WavePacketStream(const std::filesystem::path& las_path,
                                   const WaveformFacts& facts)
    : facts_(facts), descriptors_(wave_packet_descriptors(facts)) {
    auto path = las_path;
    const bool external = facts.storage == LasWaveformStorage::external;
    path.replace_extension(external ? ".wdp" : ".packets");
    file_ = std::make_unique<AtomicFile>(path);
    if (external) {
        // The .wdp file begins with the Waveform Data Packets record's header; its length is
        // unknown while the points stream, and readers take the packets up to the end of the file.
        std::uint8_t b[kLasEvlrHeaderBytes] = {};
        std::memcpy(b + 2, "LASF_Spec", 9);
        const std::uint16_t id = kLasWaveformDataRecordId;
        std::memcpy(b + 18, &id, 2);
        std::memcpy(b + 28, "Waveform Data Packets", 21);
        file_->write(b, sizeof b);
    }
}

std::vector<LasVlr> WavePacketStream::vlrs() const {
    std::vector<LasVlr> out;
    for (const auto& d : descriptors_) {
        out.push_back(las_wave_packet_descriptor_vlr(d));
    }
    return out;
}

void WavePacketStream::encode(const PointBlock& block, const LasWriter& writer,
                              LasRecordBlock& records, std::string& packets) const {
    constexpr double kPsPerM = 2.0e12 / kSpeedOfLight_m_per_s;  // round trip per one-way metre
    const double bin_ps = facts_.bin_ns * 1000.0;
    const double gain = gain_of(facts_);
    std::size_t w = 0;
    std::uint64_t last_pulse = ~std::uint64_t{0};
    LasWavePacket packet;
    for (const BlockPoint& p : block.points) {
        if (p.pulse != last_pulse) {
            last_pulse = p.pulse;
            while (w < block.waveforms.size() && block.waveforms[w].pulse < p.pulse) {
                ++w;
            }
            packet = {};
            if (w < block.waveforms.size() && block.waveforms[w].pulse == p.pulse &&
                block.waveforms[w].count > 0) {
                const PulseWaveform& f = block.waveforms[w];
                const int index = descriptor_for(f.count);
                if (index == 0) {
                    throw OutputError(file_->path().string() + ": pulse " +
                                      std::to_string(f.pulse) + ": " + std::to_string(f.count) +
                                      " samples exceed the largest wave packet (2^24)");
                }
                const std::uint32_t slots =
                    descriptors_[static_cast<std::size_t>(index - 1)].samples;
                packet.descriptor_index = static_cast<std::uint8_t>(index);
                packet.offset = packets.size();
                packet.size = 4 * slots;
                append_packet(block.samples.data() + f.first_sample, f.count, slots, gain, packets);
                const Vec3d d = f.axis * (-0.5e-12 * kSpeedOfLight_m_per_s);  // m per ps, back
                packet.dx = static_cast<float>(d.x);
                packet.dy = static_cast<float>(d.y);
                packet.dz = static_cast<float>(d.z);
            }
        }
        LasWavePacket mine = packet;
        if (mine.descriptor_index != 0) {
            const PulseWaveform& f = block.waveforms[w];
            mine.location_ps = static_cast<float>(static_cast<double>(p.range_m) * kPsPerM -
                                                  static_cast<double>(f.first_bin) * bin_ps);
        }
        writer.encode(static_cast<const LasSimplePoint&>(p), mine, records);
    }
}

void WavePacketStream::write(const LasWriter& writer, LasRecordBlock& records,
                             const std::string& packets) {
    const std::size_t field = writer.wave_packet_field();
    const std::size_t length = writer.header().point_record_length;
    for (std::size_t i = 0; i < records.count; ++i) {
        std::uint8_t* r = records.bytes.data() + i * length + field;
        if (r[0] == 0) {
            continue;
        }
        std::uint64_t offset;
        std::memcpy(&offset, r + 1, 8);
        offset += base_;
        std::memcpy(r + 1, &offset, 8);
    }
    file_->write(packets);
    base_ += packets.size();
}

std::vector<std::filesystem::path> WavePacketStream::commit(LasWriter& writer) {
    if (facts_.storage == LasWaveformStorage::internal) {
        if (std::fflush(file_->stream()) != 0) {
            throw OutputError(file_->path().string() + ": cannot flush the staged wave packets");
        }
        writer.close_with_waveform_data(file_->temp_path());
        file_.reset();  // removes the staging file
        return {writer.path()};
    }
    writer.close();
    // The record's length, now known (bytes 20-27 of its header).
    const std::uint64_t length = base_ - kLasEvlrHeaderBytes;
    if (std::fflush(file_->stream()) != 0 || ::fseeko(file_->stream(), 20, SEEK_SET) != 0 ||
        std::fwrite(&length, 8, 1, file_->stream()) != 1) {
        throw OutputError(file_->path().string() + ": cannot finish the wave packet header");
    }
    file_->commit();
    return {writer.path(), file_->path()};
}

}  // namespace beamtrace::detail
