// LAS wave packets (point formats 4, 5, 9, 10; LAS 1.4 R15): the Wave Packet Descriptor VLRs
// (LASF_Spec / 100-354), the Waveform Data Packets record (LASF_Spec / 65535, an EVLR of the LAS
// file or the start of an external `.wdp` file) and a reader that returns a point's samples.
//
// A point's packet starts `wave_data_offset` bytes after the first byte of the Waveform Data
// Packets record's 60-byte header (internal: header.start_of_waveform_data + offset in the LAS
// file; external: the offset in the `.wdp` file, which begins with that header). Sample k of the
// packet is at waveform time t_k = k * spacing after the first sample; the point lies
// wave_return_location picoseconds after the first sample, and the sample at time t lies at
//     X_P + (L - t) * (dx, dy, dz)      (X_P: the point, L: its return point waveform location),
// the spec's anchor X_0 = X_P + L * d being the first sample: d points from the target back
// towards the sensor, |d| = c / 2 per picosecond (what Leica's and LAStools' files hold).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/io/las.hpp"

namespace beamtrace {

class LasReader;

/// Record id of descriptor index 1; descriptor i is record 99 + i (i = 1-255).
inline constexpr std::uint16_t kLasWavePacketDescriptorRecordBase = 99;
/// Record id of the Waveform Data Packets record (EVLR or `.wdp` header).
inline constexpr std::uint16_t kLasWaveformDataRecordId = 65535;
/// Bytes of a Wave Packet Descriptor VLR's payload.
inline constexpr std::size_t kLasWavePacketDescriptorBytes = 26;
/// Bytes of an EVLR header (and of the `.wdp` file's header).
inline constexpr std::size_t kLasEvlrHeaderBytes = 60;

/// One Wave Packet Descriptor (its VLR payload, 26 bytes).
struct LasWavePacketDescriptor {
    int index = 1;                     ///< 1-255: the points' wave_descriptor_index
    std::uint8_t bits_per_sample = 8;  ///< 2-32 (this reader decodes 8, 16 and 32)
    std::uint8_t compression = 0;      ///< 0: none (the only value the spec defines)
    std::uint32_t samples = 0;         ///< samples per packet
    std::uint32_t spacing_ps = 0;      ///< temporal sample spacing
    double gain = 1.0;                 ///< value = offset + gain * raw
    double offset = 0.0;

    /// Bytes of an uncompressed packet: samples * bits, rounded up to whole bytes.
    [[nodiscard]] std::uint64_t packet_bytes() const {
        return (std::uint64_t{samples} * bits_per_sample + 7) / 8;
    }
    friend bool operator==(const LasWavePacketDescriptor&,
                           const LasWavePacketDescriptor&) = default;
};

/// The descriptor's VLR (LASF_Spec / 99 + index).
[[nodiscard]] LasVlr las_wave_packet_descriptor_vlr(const LasWavePacketDescriptor& d);

/// The descriptors among `vlrs` (VLRs only, not EVLRs), by index. Throws InputError naming
/// `path` for a descriptor VLR of the wrong length.
[[nodiscard]] std::vector<LasWavePacketDescriptor> las_wave_packet_descriptors(
    const std::vector<LasVlr>& vlrs, const std::filesystem::path& path);

/// Reads the wave packets of a LAS file's points: the descriptors from its VLRs, the packets
/// from its Waveform Data Packets EVLR (global encoding bit 1) or from the `.wdp` file of the
/// same name (bit 2). Every problem — no descriptor for a point's index, a packet outside the
/// packet data, a compressed or unsupported sample size, a missing `.wdp` file — throws
/// InputError naming the file.
class LasWavePacketReader {
  public:
    /// `reader`: the open LAS file (only its header, VLRs and path are used).
    explicit LasWavePacketReader(const LasReader& reader);

    [[nodiscard]] const std::vector<LasWavePacketDescriptor>& descriptors() const {
        return descriptors_;
    }
    /// The descriptor of `index`; throws InputError when the file has none.
    [[nodiscard]] const LasWavePacketDescriptor& descriptor(int index) const;
    /// The file holding the packets (the LAS file or its `.wdp`).
    [[nodiscard]] const std::filesystem::path& data_path() const { return data_path_; }
    /// Bytes of packet data after the record's header.
    [[nodiscard]] std::uint64_t data_bytes() const { return data_end_ - kLasEvlrHeaderBytes; }

    /// The raw sample values of `point`'s packet (empty for descriptor index 0).
    void raw_samples(const LasPoint& point, std::vector<std::uint32_t>& out);
    /// The samples as offset + gain * raw (the descriptor's units; beamtrace: watts).
    void samples(const LasPoint& point, std::vector<double>& out);

  private:
    [[noreturn]] void fail(const std::string& what) const;

    std::filesystem::path las_path_;
    std::filesystem::path data_path_;
    std::vector<LasWavePacketDescriptor> descriptors_;
    std::ifstream data_;
    std::uint64_t record_start_ = 0;  ///< file offset of the record's header
    std::uint64_t data_end_ = 0;      ///< end of the packet data, relative to record_start_
    std::vector<std::uint8_t> bytes_;
};

}  // namespace beamtrace
