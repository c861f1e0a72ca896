#include "beamtrace/io/las_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>

#include "beamtrace/core/error.hpp"
#include "io/detail/las_reader_laz.hpp"

namespace beamtrace {

static_assert(std::endian::native == std::endian::little,
              "the LAS reader decodes little-endian records with memcpy");

namespace {

constexpr std::size_t kVlrHeaderBytes = 54;
constexpr std::size_t kEvlrHeaderBytes = 60;
constexpr std::uint8_t kLazFormatBits = 0xC0;  // bit 7 (LASzip) or bit 6 (old LAZ writers)
constexpr std::uint16_t kLaszipRecordId = 22204;

template <typename T>
[[nodiscard]] T load(const std::uint8_t* p) {
    T value;
    std::memcpy(&value, p, sizeof(T));
    return value;
}

/// A fixed-size character field: up to its first NUL, trailing spaces removed.
[[nodiscard]] std::string load_text(const std::uint8_t* p, std::size_t size) {
    std::size_t n = 0;
    while (n < size && p[n] != 0) {
        ++n;
    }
    while (n > 0 && p[n - 1] == ' ') {
        --n;
    }
    return {reinterpret_cast<const char*>(p), n};
}

struct DecodeContext {
    Vec3d scale;
    Vec3d offset;
    std::size_t standard_size = 0;
    std::size_t record_length = 0;
};

/// Decodes one record of point format F. Sets every field, so reused points carry nothing stale.
template <int F>
void decode_record(const std::uint8_t* r, const DecodeContext& c, LasPoint& p) {
    p.x = static_cast<double>(load<std::int32_t>(r)) * c.scale.x + c.offset.x;
    p.y = static_cast<double>(load<std::int32_t>(r + 4)) * c.scale.y + c.offset.y;
    p.z = static_cast<double>(load<std::int32_t>(r + 8)) * c.scale.z + c.offset.z;
    p.intensity = load<std::uint16_t>(r + 12);
    std::size_t pos = 0;  // where the fields after the core record start
    if constexpr (las_format_is_extended(F)) {
        const std::uint8_t returns = r[14];
        const std::uint8_t flags = r[15];
        p.return_number = returns & 0x0F;
        p.number_of_returns = static_cast<std::uint8_t>(returns >> 4);
        p.synthetic = (flags & 0x01) != 0;
        p.key_point = (flags & 0x02) != 0;
        p.withheld = (flags & 0x04) != 0;
        p.overlap = (flags & 0x08) != 0;
        p.scanner_channel = static_cast<std::uint8_t>((flags >> 4) & 0x03);
        p.scan_direction = (flags & 0x40) != 0;
        p.edge_of_flight_line = (flags & 0x80) != 0;
        p.classification = r[16];
        p.user_data = r[17];
        p.scan_angle_deg = static_cast<float>(load<std::int16_t>(r + 18) * 0.006);
        p.point_source_id = load<std::uint16_t>(r + 20);
        p.gps_time = load<double>(r + 22);
        pos = 30;
    } else {
        const std::uint8_t bits = r[14];
        const std::uint8_t cls = r[15];
        p.return_number = bits & 0x07;
        p.number_of_returns = static_cast<std::uint8_t>((bits >> 3) & 0x07);
        p.scan_direction = (bits & 0x40) != 0;
        p.edge_of_flight_line = (bits & 0x80) != 0;
        p.classification = cls & 0x1F;
        p.synthetic = (cls & 0x20) != 0;
        p.key_point = (cls & 0x40) != 0;
        p.withheld = (cls & 0x80) != 0;
        p.overlap = false;
        p.scanner_channel = 0;
        p.scan_angle_deg = static_cast<float>(load<std::int8_t>(r + 16));
        p.user_data = r[17];
        p.point_source_id = load<std::uint16_t>(r + 18);
        pos = 20;
        if constexpr (las_format_has_gps_time(F)) {
            p.gps_time = load<double>(r + 20);
            pos = 28;
        } else {
            p.gps_time = 0.0;
        }
    }
    if constexpr (las_format_has_rgb(F)) {
        p.red = load<std::uint16_t>(r + pos);
        p.green = load<std::uint16_t>(r + pos + 2);
        p.blue = load<std::uint16_t>(r + pos + 4);
        pos += 6;
    } else {
        p.red = p.green = p.blue = 0;
    }
    if constexpr (las_format_has_nir(F)) {
        p.nir = load<std::uint16_t>(r + pos);
        pos += 2;
    } else {
        p.nir = 0;
    }
    if constexpr (las_format_has_wave_packet(F)) {
        p.wave_descriptor_index = r[pos];
        p.wave_data_offset = load<std::uint64_t>(r + pos + 1);
        p.wave_packet_size = load<std::uint32_t>(r + pos + 9);
        p.wave_return_location = load<float>(r + pos + 13);
        p.wave_dx = load<float>(r + pos + 17);
        p.wave_dy = load<float>(r + pos + 21);
        p.wave_dz = load<float>(r + pos + 25);
    } else {
        p.wave_descriptor_index = 0;
        p.wave_data_offset = 0;
        p.wave_packet_size = 0;
        p.wave_return_location = p.wave_dx = p.wave_dy = p.wave_dz = 0.0f;
    }
    if (c.record_length > c.standard_size) {
        p.extra_bytes.assign(r + c.standard_size, r + c.record_length);
    } else {
        p.extra_bytes.clear();
    }
}

template <int F>
void decode_records(const std::uint8_t* records, const DecodeContext& c, std::span<LasPoint> out) {
    for (std::size_t i = 0; i < out.size(); ++i) {
        decode_record<F>(records + i * c.record_length, c, out[i]);
    }
}

void decode_any(int format, const std::uint8_t* records, const DecodeContext& c,
                std::span<LasPoint> out) {
    switch (format) {
        case 0:
            return decode_records<0>(records, c, out);
        case 1:
            return decode_records<1>(records, c, out);
        case 2:
            return decode_records<2>(records, c, out);
        case 3:
            return decode_records<3>(records, c, out);
        case 4:
            return decode_records<4>(records, c, out);
        case 5:
            return decode_records<5>(records, c, out);
        case 6:
            return decode_records<6>(records, c, out);
        case 7:
            return decode_records<7>(records, c, out);
        case 8:
            return decode_records<8>(records, c, out);
        case 9:
            return decode_records<9>(records, c, out);
        default:
            return decode_records<10>(records, c, out);
    }
}

[[nodiscard]] DecodeContext context_of(const LasHeader& h) {
    return {h.scale, h.offset, las_point_record_size(h.point_format), h.point_record_length};
}

}  // namespace

LasReader::LasReader(std::filesystem::path path, unsigned threads)
    : path_(std::move(path)), threads_(threads) {
    std::error_code ec;
    if (std::filesystem::is_directory(path_, ec)) {
        fail("is a directory, not a LAS file");
    }
    fd_ = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) {
        fail(std::string("cannot open: ") + std::strerror(errno));
    }
    try {
        struct stat st {};
        if (::fstat(fd_, &st) != 0) {
            fail(std::string("cannot stat: ") + std::strerror(errno));
        }
        const auto file_size = static_cast<std::uint64_t>(st.st_size);
        parse_header(file_size);
        parse_vlrs();
        parse_evlrs(file_size);
        if (compressed_) {
            open_laz(file_size);
        }
    } catch (...) {
        ::close(fd_);
        fd_ = -1;
        throw;
    }
}

LasReader::~LasReader() {
    // A LAZ batch being decoded ahead reads through laz_ and fd_: wait for it while both are
    // whole (unique_ptr::reset nulls laz_ before destroying it).
    if (laz_ && laz_->ready.valid()) {
        laz_->ready.wait();
    }
    laz_.reset();
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

void LasReader::fail(const std::string& what) const {
    throw InputError(path_.string(), what);
}

void LasReader::read_exact(void* data, std::size_t size, std::uint64_t offset,
                           const char* what) const {
    auto* bytes = static_cast<std::uint8_t*>(data);
    std::size_t done = 0;
    while (done < size) {
        const ::ssize_t n =
            ::pread(fd_, bytes + done, size - done, static_cast<::off_t>(offset + done));
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            fail(std::string(what) + ": read failed: " + std::strerror(errno));
        }
        if (n == 0) {
            fail(std::string(what) + ": file ends at byte " + std::to_string(offset + done) + ", " +
                 std::to_string(size - done) + " bytes early");
        }
        done += static_cast<std::size_t>(n);
    }
}

void LasReader::parse_header(std::uint64_t file_size) {
    if (file_size < 4) {
        fail("header: file is " + std::to_string(file_size) + " bytes, too short for a LAS file");
    }
    std::uint8_t sig[4];
    read_exact(sig, 4, 0, "header");
    if (std::memcmp(sig, "LASF", 4) != 0) {
        fail("header: bad file signature (expected \"LASF\"): not a LAS file");
    }
    if (file_size < las_header_size(0)) {
        fail("header: file is " + std::to_string(file_size) + " bytes, shorter than the " +
             std::to_string(las_header_size(0)) + "-byte LAS header");
    }
    std::uint8_t b[375] = {};
    read_exact(b, static_cast<std::size_t>(std::min<std::uint64_t>(file_size, sizeof b)), 0,
               "header");
    LasHeader& h = header_;
    h.file_source_id = load<std::uint16_t>(b + 4);
    h.global_encoding = load<std::uint16_t>(b + 6);
    std::memcpy(h.project_guid.data(), b + 8, 16);
    h.version_major = b[24];
    h.version_minor = b[25];
    if (h.version_major != 1 || h.version_minor > 4) {
        fail("header: unsupported LAS version " + std::to_string(h.version_major) + "." +
             std::to_string(h.version_minor) + " (expected 1.0 to 1.4)");
    }
    h.system_identifier = load_text(b + 26, 32);
    h.generating_software = load_text(b + 58, 32);
    h.creation_day_of_year = load<std::uint16_t>(b + 90);
    h.creation_year = load<std::uint16_t>(b + 92);
    h.header_size = load<std::uint16_t>(b + 94);
    h.offset_to_point_data = load<std::uint32_t>(b + 96);
    h.number_of_vlrs = load<std::uint32_t>(b + 100);
    compressed_ = (b[104] & kLazFormatBits) != 0;
    const auto format_byte = static_cast<std::uint8_t>(b[104] & ~kLazFormatBits);
    if (format_byte > kLasMaxPointFormat) {
        fail("header: unknown point data record format " + std::to_string(format_byte) +
             " (expected 0 to 10)");
    }
    h.point_format = format_byte;
    h.point_record_length = load<std::uint16_t>(b + 105);
    h.legacy_point_count = load<std::uint32_t>(b + 107);
    for (std::size_t i = 0; i < 5; ++i) {
        h.legacy_points_by_return[i] = load<std::uint32_t>(b + 111 + 4 * i);
    }
    h.scale = {load<double>(b + 131), load<double>(b + 139), load<double>(b + 147)};
    h.offset = {load<double>(b + 155), load<double>(b + 163), load<double>(b + 171)};
    h.max = {load<double>(b + 179), load<double>(b + 195), load<double>(b + 211)};
    h.min = {load<double>(b + 187), load<double>(b + 203), load<double>(b + 219)};

    const std::size_t standard_header = las_header_size(h.version_minor);
    if (h.header_size < standard_header) {
        fail("header: header size " + std::to_string(h.header_size) + " is smaller than the " +
             std::to_string(standard_header) + " bytes of LAS 1." +
             std::to_string(h.version_minor));
    }
    if (file_size < h.header_size) {
        fail("header: file is " + std::to_string(file_size) + " bytes, shorter than its " +
             std::to_string(h.header_size) + "-byte header");
    }
    if (h.offset_to_point_data < h.header_size) {
        fail("header: point data offset " + std::to_string(h.offset_to_point_data) +
             " is inside the header (size " + std::to_string(h.header_size) + ")");
    }
    if (h.offset_to_point_data > file_size) {
        fail("header: point data offset " + std::to_string(h.offset_to_point_data) +
             " lies past the end of the file (" + std::to_string(file_size) + " bytes)");
    }
    const std::size_t standard_record = las_point_record_size(h.point_format);
    if (h.point_record_length < standard_record) {
        fail("header: point record length " + std::to_string(h.point_record_length) +
             " is smaller than the " + std::to_string(standard_record) + " bytes of point format " +
             std::to_string(h.point_format));
    }
    for (std::size_t k = 0; k < 3; ++k) {
        if (!std::isfinite(h.scale[k]) || h.scale[k] == 0.0 || !std::isfinite(h.offset[k])) {
            fail(std::string("header: ") + "xyz"[k] + " scale " + std::to_string(h.scale[k]) +
                 " / offset " + std::to_string(h.offset[k]) + " is not usable");
        }
    }

    h.point_count = h.legacy_point_count;
    for (std::size_t i = 0; i < 5; ++i) {
        h.points_by_return[i] = h.legacy_points_by_return[i];
    }
    if (h.version_minor >= 3) {
        h.start_of_waveform_data = load<std::uint64_t>(b + 227);
    }
    if (h.version_minor >= 4) {
        h.start_of_first_evlr = load<std::uint64_t>(b + 235);
        h.number_of_evlrs = load<std::uint32_t>(b + 243);
        const auto count = load<std::uint64_t>(b + 247);
        // Some writers fill only the legacy fields: fall back to them when the 64-bit ones are 0.
        if (count != 0 || h.legacy_point_count == 0) {
            h.point_count = count;
            for (std::size_t i = 0; i < 15; ++i) {
                h.points_by_return[i] = load<std::uint64_t>(b + 255 + 8 * i);
            }
        }
    }
    const std::uint64_t available =
        file_size > h.offset_to_point_data ? file_size - h.offset_to_point_data : 0;
    const std::uint64_t complete = available / h.point_record_length;
    if (!compressed_ && h.point_count > complete) {
        fail("point data: header says " + std::to_string(h.point_count) +
             " points but the file holds only " + std::to_string(complete) + " (" +
             std::to_string(h.point_record_length) + "-byte records from byte " +
             std::to_string(h.offset_to_point_data) + " of " + std::to_string(file_size) +
             "): the file is truncated");
    }
}

void LasReader::parse_vlrs() {
    const LasHeader& h = header_;
    std::uint64_t pos = h.header_size;
    const std::uint64_t end = h.offset_to_point_data;
    std::uint8_t b[kVlrHeaderBytes];
    for (std::uint32_t i = 0; i < h.number_of_vlrs; ++i) {
        const std::string where =
            "VLR " + std::to_string(i + 1) + " of " + std::to_string(h.number_of_vlrs);
        if (pos + kVlrHeaderBytes > end) {
            fail(where + ": its header at byte " + std::to_string(pos) +
                 " runs past the start of the point data at byte " + std::to_string(end));
        }
        read_exact(b, kVlrHeaderBytes, pos, "VLR");
        LasVlr v;
        v.user_id = load_text(b + 2, 16);
        v.record_id = load<std::uint16_t>(b + 18);
        v.length = load<std::uint16_t>(b + 20);
        v.description = load_text(b + 22, 32);
        pos += kVlrHeaderBytes;
        if (pos + v.length > end) {
            fail(where + " (" + v.user_id + "/" + std::to_string(v.record_id) + "): its " +
                 std::to_string(v.length) + " bytes of data at byte " + std::to_string(pos) +
                 " run past the start of the point data at byte " + std::to_string(end));
        }
        if (v.user_id == "laszip encoded" && v.record_id == kLaszipRecordId) {
            laszip_vlr_ = vlrs_.size() + 1;
        }
        v.data.resize(static_cast<std::size_t>(v.length));
        read_exact(v.data.data(), v.data.size(), pos, "VLR");
        pos += v.length;
        vlrs_.push_back(std::move(v));
    }
}

void LasReader::parse_evlrs(std::uint64_t file_size) {
    const LasHeader& h = header_;
    if (h.number_of_evlrs == 0) {
        return;
    }
    const std::uint64_t points_end =
        compressed_ ? h.offset_to_point_data
                    : h.offset_to_point_data + h.point_count * std::uint64_t{h.point_record_length};
    if (h.start_of_first_evlr < points_end) {
        fail("header: first EVLR at byte " + std::to_string(h.start_of_first_evlr) +
             " starts before the end of the point data at byte " + std::to_string(points_end));
    }
    std::uint64_t pos = h.start_of_first_evlr;
    std::uint8_t b[kEvlrHeaderBytes];
    for (std::uint32_t i = 0; i < h.number_of_evlrs; ++i) {
        const std::string where =
            "EVLR " + std::to_string(i + 1) + " of " + std::to_string(h.number_of_evlrs);
        if (pos > file_size || file_size - pos < kEvlrHeaderBytes) {
            fail(where + ": its header at byte " + std::to_string(pos) +
                 " runs past the end of the file (" + std::to_string(file_size) + " bytes)");
        }
        read_exact(b, kEvlrHeaderBytes, pos, "EVLR");
        LasVlr v;
        v.extended = true;
        v.user_id = load_text(b + 2, 16);
        v.record_id = load<std::uint16_t>(b + 18);
        v.length = load<std::uint64_t>(b + 20);
        v.description = load_text(b + 28, 32);
        pos += kEvlrHeaderBytes;
        if (v.length > file_size - pos) {
            fail(where + " (" + v.user_id + "/" + std::to_string(v.record_id) + "): its " +
                 std::to_string(v.length) + " bytes of data at byte " + std::to_string(pos) +
                 " run past the end of the file (" + std::to_string(file_size) + " bytes)");
        }
        if (v.length <= kMaxLoadedEvlrBytes) {
            v.data.resize(static_cast<std::size_t>(v.length));
            read_exact(v.data.data(), v.data.size(), pos, "EVLR");
        }
        pos += v.length;
        vlrs_.push_back(std::move(v));
    }
}

void LasReader::fill_chunk() {
    if (laz_) {
        fill_laz_chunk();
        return;
    }
    const std::size_t n = static_cast<std::size_t>(
        std::min<std::uint64_t>(kChunkPoints, header_.point_count - file_next_));
    const std::size_t bytes = n * header_.point_record_length;
    if (chunk_.size() < bytes) {
        chunk_.resize(bytes);
    }
    const std::uint64_t offset =
        header_.offset_to_point_data + file_next_ * std::uint64_t{header_.point_record_length};
    read_exact(chunk_.data(), bytes, offset, "point data");
    chunk_points_ = n;
    chunk_next_ = 0;
    file_next_ += n;
}

std::size_t LasReader::read(std::span<LasPoint> out) {
    const DecodeContext context = context_of(header_);
    std::size_t done = 0;
    while (done < out.size() && next_ < header_.point_count) {
        if (chunk_next_ == chunk_points_) {
            fill_chunk();
        }
        const std::size_t n = std::min(out.size() - done, chunk_points_ - chunk_next_);
        decode_any(header_.point_format, chunk_.data() + chunk_next_ * context.record_length,
                   context, out.subspan(done, n));
        chunk_next_ += n;
        done += n;
        next_ += n;
    }
    return done;
}

std::size_t LasReader::read_records(std::span<std::uint8_t> out) {
    const std::size_t length = header_.point_record_length;
    const std::size_t want = out.size() / length;
    std::size_t done = 0;
    while (done < want && next_ < header_.point_count) {
        if (chunk_next_ == chunk_points_) {
            fill_chunk();
        }
        const std::size_t n = std::min(want - done, chunk_points_ - chunk_next_);
        std::memcpy(out.data() + done * length, chunk_.data() + chunk_next_ * length, n * length);
        chunk_next_ += n;
        done += n;
        next_ += n;
    }
    return done;
}

void LasReader::seek(std::uint64_t index) {
    if (index > header_.point_count) {
        throw InputError(path_.string(), "seek to point " + std::to_string(index) +
                                             " past the end (" +
                                             std::to_string(header_.point_count) + " points)");
    }
    next_ = file_next_ = index;
    chunk_points_ = chunk_next_ = 0;
    if (laz_) {
        seek_laz(index);
    }
}

void LasReader::decode(const std::uint8_t* record, LasPoint& out) const {
    decode_any(header_.point_format, record, context_of(header_), std::span(&out, 1));
}

std::vector<LasPoint> read_las_points(const std::filesystem::path& path) {
    LasReader reader(path);
    std::vector<LasPoint> points(static_cast<std::size_t>(reader.header().point_count));
    const std::size_t n = reader.read(points);
    points.resize(n);
    return points;
}

}  // namespace beamtrace
