// Independent readers for the survey's outputs, written from the format specifications (LAS 1.4
// R15, docs/survey.md's waveforms.bin, the PLY 1.0 spec) rather than with the library's readers,
// so a test that uses them checks the writers against the specification, not against
// themselves.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "beamtrace/pipeline/survey.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace::test {

/// Reads a little-endian T at byte `at` of `bytes` (failing the test past the end).
template <typename T>
T get_le(const std::string& bytes, std::size_t at) {
    T value{};
    if (at + sizeof(T) > bytes.size()) {
        ADD_FAILURE() << "read of " << sizeof(T) << " bytes at " << at << " past the end ("
                      << bytes.size() << ")";
        return value;
    }
    std::memcpy(&value, bytes.data() + at, sizeof(T));
    return value;
}

/// A fixed-size, NUL-padded text field.
inline std::string get_text(const std::string& bytes, std::size_t at, std::size_t size) {
    std::string s = bytes.substr(at, size);
    return s.substr(0, s.find('\0'));
}

/// One LAS point record of formats 6-8, field by field as the LAS 1.4 R15 tables lay it out.
struct RawLasPoint {
    std::int32_t ix = 0, iy = 0, iz = 0;  ///< the stored integers
    double x = 0, y = 0, z = 0;           ///< integer * scale + offset
    std::uint16_t intensity = 0;
    int return_number = 0, number_of_returns = 0;
    std::uint8_t flags = 0, classification = 0, user_data = 0;
    std::int16_t scan_angle = 0;  ///< 0.006 degree steps
    std::uint16_t point_source_id = 0;
    double gps_time = 0;
    std::array<std::uint16_t, 3> rgb{};
    std::uint16_t nir = 0;
    std::string base;  ///< bytes 0-29, common to formats 6-8

    [[nodiscard]] double scan_angle_deg() const { return scan_angle * 0.006; }
};

struct RawLasVlr {
    std::string user_id;
    std::uint16_t record_id = 0;
    std::string description;
    std::string data;
};

/// A LAS 1.4 file: the header fields the tests need, the VLRs and the points.
struct RawLas {
    std::uint16_t global_encoding = 0;
    int version_major = 0, version_minor = 0;
    std::string system_identifier, generating_software;
    std::uint16_t header_size = 0;
    std::uint32_t point_offset = 0, vlr_count = 0;
    int point_format = 0;
    std::uint16_t record_length = 0;
    std::uint32_t legacy_count = 0;
    std::array<std::uint32_t, 5> legacy_by_return{};
    std::array<double, 3> scale{}, offset{}, min{}, max{};
    std::uint64_t point_count = 0;
    std::array<std::uint64_t, 15> by_return{};
    std::vector<RawLasVlr> vlrs;
    std::vector<RawLasPoint> points;
};

inline RawLasPoint parse_las_record(const std::string& b, std::size_t at, const RawLas& las) {
    RawLasPoint p;
    p.ix = get_le<std::int32_t>(b, at);
    p.iy = get_le<std::int32_t>(b, at + 4);
    p.iz = get_le<std::int32_t>(b, at + 8);
    p.x = p.ix * las.scale[0] + las.offset[0];
    p.y = p.iy * las.scale[1] + las.offset[1];
    p.z = p.iz * las.scale[2] + las.offset[2];
    p.intensity = get_le<std::uint16_t>(b, at + 12);
    const auto returns = get_le<std::uint8_t>(b, at + 14);
    p.return_number = returns & 0x0F;
    p.number_of_returns = returns >> 4;
    p.flags = get_le<std::uint8_t>(b, at + 15);
    p.classification = get_le<std::uint8_t>(b, at + 16);
    p.user_data = get_le<std::uint8_t>(b, at + 17);
    p.scan_angle = get_le<std::int16_t>(b, at + 18);
    p.point_source_id = get_le<std::uint16_t>(b, at + 20);
    p.gps_time = get_le<double>(b, at + 22);
    p.base = b.substr(at, 30);
    if (las.point_format >= 7) {
        for (std::size_t c = 0; c < 3; ++c) {
            p.rgb[c] = get_le<std::uint16_t>(b, at + 30 + 2 * c);
        }
    }
    if (las.point_format == 8) {
        p.nir = get_le<std::uint16_t>(b, at + 36);
    }
    return p;
}

/// Parses a whole LAS 1.4 file (header at the R15 offsets, VLRs, point records).
inline RawLas parse_las(const std::string& b) {
    RawLas las;
    EXPECT_EQ(b.substr(0, 4), "LASF");
    las.global_encoding = get_le<std::uint16_t>(b, 6);
    las.version_major = get_le<std::uint8_t>(b, 24);
    las.version_minor = get_le<std::uint8_t>(b, 25);
    las.system_identifier = get_text(b, 26, 32);
    las.generating_software = get_text(b, 58, 32);
    las.header_size = get_le<std::uint16_t>(b, 94);
    las.point_offset = get_le<std::uint32_t>(b, 96);
    las.vlr_count = get_le<std::uint32_t>(b, 100);
    las.point_format = get_le<std::uint8_t>(b, 104);
    las.record_length = get_le<std::uint16_t>(b, 105);
    las.legacy_count = get_le<std::uint32_t>(b, 107);
    for (std::size_t i = 0; i < 5; ++i) {
        las.legacy_by_return[i] = get_le<std::uint32_t>(b, 111 + 4 * i);
    }
    for (std::size_t k = 0; k < 3; ++k) {
        las.scale[k] = get_le<double>(b, 131 + 8 * k);
        las.offset[k] = get_le<double>(b, 155 + 8 * k);
        las.max[k] = get_le<double>(b, 179 + 16 * k);
        las.min[k] = get_le<double>(b, 187 + 16 * k);
    }
    las.point_count = get_le<std::uint64_t>(b, 247);
    for (std::size_t i = 0; i < 15; ++i) {
        las.by_return[i] = get_le<std::uint64_t>(b, 255 + 8 * i);
    }
    std::size_t at = las.header_size;
    for (std::uint32_t v = 0; v < las.vlr_count && at + 54 <= b.size(); ++v) {
        RawLasVlr vlr;
        vlr.user_id = get_text(b, at + 2, 16);
        vlr.record_id = get_le<std::uint16_t>(b, at + 18);
        const auto length = get_le<std::uint16_t>(b, at + 20);
        vlr.description = get_text(b, at + 22, 32);
        vlr.data = b.substr(at + 54, length);
        at += 54u + length;
        las.vlrs.push_back(std::move(vlr));
    }
    EXPECT_EQ(at, las.point_offset) << "the VLRs end where the points begin";
    const std::size_t end = las.point_offset + las.point_count * las.record_length;
    EXPECT_LE(end, b.size()) << "point records past the end of the file";
    for (std::size_t r = las.point_offset; r + las.record_length <= std::min(end, b.size());
         r += las.record_length) {
        las.points.push_back(parse_las_record(b, r, las));
    }
    return las;
}

/// Writes `yaml` as survey.yaml in `dir`, runs it into dir/out and parses dir/out/points.las.
inline RawLas run_survey_raw(const std::string& yaml, const TempDir& dir, std::uint64_t seed = 1,
                             unsigned threads = 2, std::size_t chunk = std::size_t{1} << 16) {
    run_survey_in(yaml, dir, threads, chunk, seed);
    return parse_las(read_file(dir / "out" / "points.las"));
}

/// One waveforms.bin record (docs/survey.md).
struct WaveRecord {
    std::uint64_t pulse = 0;
    double gps_time = 0;
    std::array<double, 3> origin{}, axis{};
    std::int64_t first_bin = 0;
    std::vector<float> samples;
};

struct WaveFile {
    double bin_ns = 0, fwhm_ns = 0;
    std::vector<WaveRecord> records;
    std::size_t bytes_read = 0;  ///< where the last record ended
};

/// Parses waveforms.bin: the 32-byte header, then records back to back until the end.
inline WaveFile parse_waveforms(const std::string& b) {
    WaveFile w;
    EXPECT_EQ(b.substr(0, 8), "BTWAVE01");
    EXPECT_EQ(get_le<std::uint32_t>(b, 8), 1u);
    EXPECT_EQ(get_le<std::uint32_t>(b, 12), 0u);
    w.bin_ns = get_le<double>(b, 16);
    w.fwhm_ns = get_le<double>(b, 24);
    std::size_t at = 32;
    while (at + 76 <= b.size()) {
        WaveRecord r;
        r.pulse = get_le<std::uint64_t>(b, at);
        r.gps_time = get_le<double>(b, at + 8);
        for (std::size_t k = 0; k < 3; ++k) {
            r.origin[k] = get_le<double>(b, at + 16 + 8 * k);
            r.axis[k] = get_le<double>(b, at + 40 + 8 * k);
        }
        r.first_bin = get_le<std::int64_t>(b, at + 64);
        const auto n = get_le<std::uint32_t>(b, at + 72);
        at += 76;
        if (at + 4u * n > b.size()) {
            ADD_FAILURE() << "record of pulse " << r.pulse << " runs past the end";
            break;
        }
        r.samples.resize(n);
        if (n > 0) {  // a miss: no samples, and data() may be null
            std::memcpy(r.samples.data(), b.data() + at, 4u * n);
        }
        at += 4u * n;
        w.records.push_back(std::move(r));
    }
    w.bytes_read = at;
    return w;
}

/// One vertex of the survey's points.ply (docs/formats.md).
struct PlyVertex {
    double x = 0, y = 0, z = 0;
    float range = 0;
    std::int32_t face_id = 0;
    std::uint32_t ray = 0;
};

/// Parses a binary little-endian PLY whose only element is `vertex` with the properties
/// double x, y, z, float range, int face_id, uint ray (checked line by line).
inline std::vector<PlyVertex> parse_points_ply(const std::string& b) {
    const std::size_t end = b.find("end_header\n");
    if (end == std::string::npos) {
        ADD_FAILURE() << "no end_header";
        return {};
    }
    std::istringstream header(b.substr(0, end));
    std::string line;
    std::vector<std::string> properties;
    std::size_t count = 0;
    std::getline(header, line);
    EXPECT_EQ(line, "ply");
    std::getline(header, line);
    EXPECT_EQ(line, "format binary_little_endian 1.0");
    while (std::getline(header, line)) {
        if (line.rfind("element vertex ", 0) == 0) {
            count = std::stoul(line.substr(15));
        } else if (line.rfind("property ", 0) == 0) {
            properties.push_back(line);
        } else {
            EXPECT_EQ(line.rfind("comment ", 0), 0u) << line;
        }
    }
    EXPECT_EQ(properties, (std::vector<std::string>{"property double x", "property double y",
                                                    "property double z", "property float range",
                                                    "property int face_id", "property uint ray"}));
    const std::size_t body = end + 11;
    constexpr std::size_t kRecord = 3 * 8 + 4 + 4 + 4;
    EXPECT_EQ(b.size(), body + count * kRecord) << "body size for " << count << " vertices";
    std::vector<PlyVertex> v(count);
    for (std::size_t i = 0; i < count && body + (i + 1) * kRecord <= b.size(); ++i) {
        const std::size_t at = body + i * kRecord;
        v[i] = {get_le<double>(b, at),
                get_le<double>(b, at + 8),
                get_le<double>(b, at + 16),
                get_le<float>(b, at + 24),
                get_le<std::int32_t>(b, at + 28),
                get_le<std::uint32_t>(b, at + 32)};
    }
    return v;
}

}  // namespace beamtrace::test
