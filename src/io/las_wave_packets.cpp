#include "beamtrace/io/las_wave_packets.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"

namespace beamtrace {

namespace {

constexpr const char* kLasfSpec = "LASF_Spec";

template <typename T>
T load(const std::uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

template <typename T>
void put(std::vector<std::uint8_t>& out, T value) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&value);
    out.insert(out.end(), p, p + sizeof value);
}

[[nodiscard]] bool is_descriptor(const LasVlr& v) {
    return !v.extended && v.user_id == kLasfSpec &&
           v.record_id > kLasWavePacketDescriptorRecordBase &&
           v.record_id <= kLasWavePacketDescriptorRecordBase + 255;
}

[[nodiscard]] std::uint64_t packet_file_size(const std::filesystem::path& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) {
        throw InputError(path.string(), "cannot read the waveform data: " + ec.message());
    }
    return size;
}

}  // namespace

LasVlr las_wave_packet_descriptor_vlr(const LasWavePacketDescriptor& d) {
    LasVlr v;
    v.user_id = kLasfSpec;
    v.record_id = static_cast<std::uint16_t>(kLasWavePacketDescriptorRecordBase + d.index);
    v.description = "Waveform Packet Descriptor";
    v.data.reserve(kLasWavePacketDescriptorBytes);
    put(v.data, d.bits_per_sample);
    put(v.data, d.compression);
    put(v.data, d.samples);
    put(v.data, d.spacing_ps);
    put(v.data, d.gain);
    put(v.data, d.offset);
    v.length = v.data.size();
    return v;
}

std::vector<LasWavePacketDescriptor> las_wave_packet_descriptors(
    const std::vector<LasVlr>& vlrs, const std::filesystem::path& path) {
    std::vector<LasWavePacketDescriptor> out;
    for (const LasVlr& v : vlrs) {
        if (!is_descriptor(v)) {
            continue;
        }
        // Some writers pad the record; 26 bytes are the descriptor.
        if (v.data.size() < kLasWavePacketDescriptorBytes) {
            throw InputError(path.string(),
                             "wave packet descriptor VLR " + std::to_string(v.record_id) +
                                 " holds " + std::to_string(v.data.size()) + " bytes, expected 26");
        }
        const std::uint8_t* b = v.data.data();
        LasWavePacketDescriptor d;
        d.index = v.record_id - kLasWavePacketDescriptorRecordBase;
        d.bits_per_sample = b[0];
        d.compression = b[1];
        d.samples = load<std::uint32_t>(b + 2);
        d.spacing_ps = load<std::uint32_t>(b + 6);
        d.gain = load<double>(b + 10);
        d.offset = load<double>(b + 18);
        out.push_back(d);
    }
    std::sort(out.begin(), out.end(),
              [](const auto& a, const auto& b) { return a.index < b.index; });
    return out;
}

LasWavePacketReader::LasWavePacketReader(const LasReader& reader)
    : las_path_(reader.path()),
      descriptors_(las_wave_packet_descriptors(reader.vlrs(), las_path_)) {
    const LasHeader& h = reader.header();
    const bool internal = (h.global_encoding & kLasGlobalEncodingInternalWaveform) != 0;
    const bool external = (h.global_encoding & kLasGlobalEncodingExternalWaveform) != 0;
    if (internal == external) {
        fail(internal ? "global encoding has both waveform bits (1: internal, 2: external) set"
                      : "global encoding says the file has no waveform data (bits 1 and 2 clear)");
    }
    if (internal) {
        data_path_ = las_path_;
        record_start_ = h.start_of_waveform_data;
        if (record_start_ == 0) {
            fail("internal waveform data, but the start of the waveform data packet record is 0");
        }
    } else {
        data_path_ = las_path_;
        data_path_.replace_extension(".wdp");
        if (!std::filesystem::exists(data_path_)) {
            auto upper = las_path_;
            upper.replace_extension(".WDP");
            data_path_ = std::filesystem::exists(upper) ? upper : data_path_;
        }
        if (!std::filesystem::exists(data_path_)) {
            fail("the waveform data packets are external, but " + data_path_.string() +
                 " does not exist");
        }
    }
    const std::uint64_t size = packet_file_size(data_path_);
    if (record_start_ > size || size - record_start_ < kLasEvlrHeaderBytes) {
        fail("the waveform data packet record at byte " + std::to_string(record_start_) +
             " lies outside " + data_path_.string() + " (" + std::to_string(size) + " bytes)");
    }
    data_.open(data_path_, std::ios::binary);
    if (!data_) {
        fail("cannot open " + data_path_.string());
    }
    std::uint8_t header[kLasEvlrHeaderBytes];
    data_.seekg(static_cast<std::streamoff>(record_start_));
    data_.read(reinterpret_cast<char*>(header), sizeof header);
    const std::uint64_t available = size - record_start_;
    if (data_ && load<std::uint16_t>(header + 18) == kLasWaveformDataRecordId) {
        const std::uint64_t length = load<std::uint64_t>(header + 20);
        data_end_ = kLasEvlrHeaderBytes + std::min(length, available - kLasEvlrHeaderBytes);
    } else {
        fail("no waveform data packet record (record id 65535) at byte " +
             std::to_string(record_start_) + " of " + data_path_.string());
    }
}

void LasWavePacketReader::fail(const std::string& what) const {
    throw InputError(las_path_.string(), what);
}

const LasWavePacketDescriptor& LasWavePacketReader::descriptor(int index) const {
    for (const auto& d : descriptors_) {
        if (d.index == index) {
            return d;
        }
    }
    fail("wave packet descriptor index " + std::to_string(index) +
         " has no descriptor VLR (LASF_Spec / " +
         std::to_string(kLasWavePacketDescriptorRecordBase + index) + ")");
}

void LasWavePacketReader::raw_samples(const LasPoint& p, std::vector<std::uint32_t>& out) {
    out.clear();
    if (p.wave_descriptor_index == 0) {
        return;
    }
    const LasWavePacketDescriptor& d = descriptor(p.wave_descriptor_index);
    const std::string which = "descriptor " + std::to_string(d.index) + ": ";
    if (d.compression != 0) {
        fail(which + "waveform compression type " + std::to_string(d.compression) +
             " is not supported (only 0)");
    }
    if (d.bits_per_sample != 8 && d.bits_per_sample != 16 && d.bits_per_sample != 32) {
        fail(which + std::to_string(d.bits_per_sample) +
             " bits per sample are not supported (8, 16 or 32)");
    }
    const std::uint64_t need = d.packet_bytes();
    const std::uint64_t begin = p.wave_data_offset;
    if (p.wave_packet_size < need || begin < kLasEvlrHeaderBytes || begin > data_end_ ||
        data_end_ - begin < need) {
        fail("wave packet at byte offset " + std::to_string(begin) + " (" +
             std::to_string(p.wave_packet_size) + " bytes, descriptor " + std::to_string(d.index) +
             ": " + std::to_string(need) + ") lies outside the waveform data (bytes 60-" +
             std::to_string(data_end_) + " of the record)");
    }
    bytes_.resize(static_cast<std::size_t>(need));
    data_.clear();
    data_.seekg(static_cast<std::streamoff>(record_start_ + begin));
    data_.read(reinterpret_cast<char*>(bytes_.data()), static_cast<std::streamsize>(need));
    if (!data_) {
        fail("cannot read the wave packet at byte offset " + std::to_string(begin));
    }
    out.resize(d.samples);
    const std::size_t width = d.bits_per_sample / 8u;
    for (std::size_t k = 0; k < out.size(); ++k) {
        const std::uint8_t* s = bytes_.data() + k * width;
        out[k] = width == 1 ? s[0] : (width == 2 ? load<std::uint16_t>(s) : load<std::uint32_t>(s));
    }
}

void LasWavePacketReader::samples(const LasPoint& p, std::vector<double>& out) {
    std::vector<std::uint32_t> raw;
    raw_samples(p, raw);
    out.resize(raw.size());
    if (raw.empty()) {
        return;
    }
    const LasWavePacketDescriptor& d = descriptor(p.wave_descriptor_index);
    for (std::size_t k = 0; k < raw.size(); ++k) {
        out[k] = d.offset + d.gain * static_cast<double>(raw[k]);
    }
}

}  // namespace beamtrace
