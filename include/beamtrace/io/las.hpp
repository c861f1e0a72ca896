// ASPRS LAS point-cloud files (versions 1.0-1.4, point data record formats 0-10): the header,
// variable length records and points as plain values shared by LasReader and LasWriter.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// Global encoding bit 0: GPS times are adjusted standard GPS time (seconds since the GPS epoch
/// minus 1e9) rather than GPS week time.
inline constexpr std::uint16_t kLasGlobalEncodingStandardGpsTime = 1u << 0;
/// Global encoding bit 1 (LAS 1.3+): waveform data packets are inside this file (deprecated).
inline constexpr std::uint16_t kLasGlobalEncodingInternalWaveform = 1u << 1;
/// Global encoding bit 2 (LAS 1.3+): waveform data packets are in an external `.wdp` file.
inline constexpr std::uint16_t kLasGlobalEncodingExternalWaveform = 1u << 2;
/// Global encoding bit 3 (LAS 1.3+): return numbers were generated synthetically.
inline constexpr std::uint16_t kLasGlobalEncodingSyntheticReturns = 1u << 3;
/// Global encoding bit 4 (LAS 1.4): the coordinate reference system is WKT (required for point
/// formats 6-10).
inline constexpr std::uint16_t kLasGlobalEncodingWkt = 1u << 4;

/// The highest point data record format defined by LAS 1.4.
inline constexpr int kLasMaxPointFormat = 10;

/// Bytes of a point record of `format` without extra bytes; 0 for an unknown format.
[[nodiscard]] constexpr std::size_t las_point_record_size(int format) {
    constexpr std::array<std::size_t, 11> sizes = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
    return format >= 0 && format <= kLasMaxPointFormat ? sizes[static_cast<std::size_t>(format)]
                                                       : 0;
}
/// Formats 6-10 use the LAS 1.4 layout (15 returns, 256 classes, scanner channel, 16-bit angle).
[[nodiscard]] constexpr bool las_format_is_extended(int format) {
    return format >= 6;
}
[[nodiscard]] constexpr bool las_format_has_gps_time(int format) {
    return format == 1 || format >= 3;
}
[[nodiscard]] constexpr bool las_format_has_rgb(int format) {
    return format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
}
[[nodiscard]] constexpr bool las_format_has_nir(int format) {
    return format == 8 || format == 10;
}
[[nodiscard]] constexpr bool las_format_has_wave_packet(int format) {
    return format == 4 || format == 5 || format == 9 || format == 10;
}

/// Bytes of the public header block of a LAS 1.<minor> file: 227 (1.0-1.2), 235 (1.3), 375 (1.4).
[[nodiscard]] constexpr std::size_t las_header_size(int version_minor) {
    return version_minor >= 4 ? 375 : (version_minor == 3 ? 235 : 227);
}

/// The public header block. Counts are always the 64-bit values: for files before LAS 1.4 (or
/// LAS 1.4 files whose 64-bit fields are zero) they are copied from the legacy 32-bit fields.
struct LasHeader {
    int version_major = 1;
    int version_minor = 4;
    std::uint16_t file_source_id = 0;
    std::uint16_t global_encoding = 0;  ///< kLasGlobalEncoding* bits
    std::array<std::uint8_t, 16> project_guid{};
    std::string system_identifier;    ///< up to 32 characters
    std::string generating_software;  ///< up to 32 characters
    std::uint16_t creation_day_of_year = 0;
    std::uint16_t creation_year = 0;
    std::uint16_t header_size = 375;  ///< may exceed las_header_size(): extra bytes are skipped
    std::uint32_t offset_to_point_data = 375;
    std::uint32_t number_of_vlrs = 0;
    int point_format = 6;                    ///< 0-10 (the LAZ bits are rejected by the reader)
    std::uint16_t point_record_length = 30;  ///< >= las_point_record_size(point_format)
    std::uint32_t legacy_point_count = 0;
    std::array<std::uint32_t, 5> legacy_points_by_return{};
    std::uint64_t point_count = 0;
    std::array<std::uint64_t, 15> points_by_return{};  ///< [0] = first returns
    Vec3d scale{0.001, 0.001, 0.001};
    Vec3d offset{0.0, 0.0, 0.0};
    Vec3d min{0.0, 0.0, 0.0};
    Vec3d max{0.0, 0.0, 0.0};
    std::uint64_t start_of_waveform_data = 0;  ///< LAS 1.3+
    std::uint64_t start_of_first_evlr = 0;     ///< LAS 1.4
    std::uint32_t number_of_evlrs = 0;         ///< LAS 1.4

    [[nodiscard]] bool gps_time_is_standard() const {
        return (global_encoding & kLasGlobalEncodingStandardGpsTime) != 0;
    }
    [[nodiscard]] bool crs_is_wkt() const { return (global_encoding & kLasGlobalEncodingWkt) != 0; }
    /// Bytes per point beyond the standard record of the format.
    [[nodiscard]] std::size_t extra_bytes_per_point() const {
        return point_record_length - las_point_record_size(point_format);
    }
};

/// A variable length record (VLR, payload < 64 KiB, before the points) or an extended one (EVLR,
/// LAS 1.4, after the points).
struct LasVlr {
    std::string user_id;  ///< up to 16 characters
    std::uint16_t record_id = 0;
    std::string description;  ///< up to 32 characters
    std::vector<std::uint8_t> data;
    bool extended = false;
    /// Payload bytes in the file. Equal to data.size() except for EVLRs too large for the reader
    /// to load (waveform data): their `data` stays empty. The writer ignores it.
    std::uint64_t length = 0;
};

/// One point with every field of formats 0-10. Fields a format does not store read as 0.
struct LasPoint {
    double x = 0.0, y = 0.0, z = 0.0;  ///< scaled and offset
    double gps_time = 0.0;             ///< formats 1, 3-10
    float scan_angle_deg = 0.0f;       ///< formats 0-5: the integer rank; 6-10: the 0.006 deg steps
    std::uint16_t intensity = 0;
    std::uint8_t return_number = 0;      ///< 1-5 (formats 0-5) or 1-15 (6-10)
    std::uint8_t number_of_returns = 0;  ///< 1-5 or 1-15
    std::uint8_t classification = 0;     ///< 0-31 (formats 0-5, flags removed) or 0-255
    bool synthetic = false;
    bool key_point = false;
    bool withheld = false;
    bool overlap = false;              ///< formats 6-10
    std::uint8_t scanner_channel = 0;  ///< 0-3, formats 6-10
    bool scan_direction = false;       ///< 1: positive scan direction
    bool edge_of_flight_line = false;
    std::uint8_t user_data = 0;
    std::uint16_t point_source_id = 0;
    std::uint16_t red = 0, green = 0, blue = 0;  ///< formats 2, 3, 5, 7, 8, 10
    std::uint16_t nir = 0;                       ///< formats 8, 10
    // Wave packet (formats 4, 5, 9, 10).
    std::uint8_t wave_descriptor_index = 0;
    std::uint64_t wave_data_offset = 0;
    std::uint32_t wave_packet_size = 0;
    float wave_return_location = 0.0f;  ///< picoseconds from the first digitized sample
    float wave_dx = 0.0f, wave_dy = 0.0f, wave_dz = 0.0f;  ///< x(t), y(t), z(t)
    /// The bytes after the standard record (empty when the record length is standard).
    std::vector<std::uint8_t> extra_bytes;

    friend bool operator==(const LasPoint&, const LasPoint&) = default;
};

}  // namespace beamtrace
