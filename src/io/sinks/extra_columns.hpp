// output.extra_bytes in the text and binary point files (CSV, PLY, PCD): the attributes of
// io/point_attributes.hpp as columns / properties named as their LAS extra-bytes dimensions
// (range_m, incidence_angle_deg, echo_width_ns, beam, object_id, instance_id, velocity_x/y/z,
// weather), in the order listed.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>

#include "beamtrace/io/point_attributes.hpp"
#include "beamtrace/io/point_sink.hpp"

namespace beamtrace::detail {

/// The LAS dimension name of `a` (its Extra Bytes descriptor's).
[[nodiscard]] inline std::string extra_column_name(PointAttribute a) {
    return point_attribute_descriptor(a).name;
}

/// The integer type of `a` in the text and binary files: that of its unscaled integer LAS field
/// (beam, object_id, instance_id, weather); the others are float32 measurements.
[[nodiscard]] inline LasExtraType extra_column_integer_type(PointAttribute a) {
    const LasExtraBytesDescriptor d = point_attribute_descriptor(a);
    const bool integer =
        d.scale == 1.0 && d.data_type != LasExtraType::f32 && d.data_type != LasExtraType::f64;
    return integer ? d.data_type : LasExtraType::undocumented;
}

/// Whether `a` is an integer rather than a measurement.
[[nodiscard]] inline bool extra_column_is_integer(PointAttribute a) {
    return extra_column_integer_type(a) != LasExtraType::undocumented;
}

/// The value of `a` at point `p` (what the LAS sink encodes): a NaN echo width is unknown.
[[nodiscard]] inline double extra_column_value(PointAttribute a, const BlockPoint& p) {
    switch (a) {
        case PointAttribute::range:
            return p.range_m;
        case PointAttribute::incidence_angle:
            return p.incidence_deg;
        case PointAttribute::echo_width:
            return p.echo_width_ns;
        case PointAttribute::beam:
            return p.channel;
        case PointAttribute::object_id:
            return p.point_source_id;
        case PointAttribute::instance_id:
            return p.instance_id;
        case PointAttribute::velocity_x:
            return p.velocity_mps.x;
        case PointAttribute::velocity_y:
            return p.velocity_mps.y;
        case PointAttribute::velocity_z:
            return p.velocity_mps.z;
        case PointAttribute::weather:
            return p.weather;
    }
    return 0.0;
}

/// Bytes of `a` in a binary record: its integer type's, or 4 (float32).
[[nodiscard]] inline std::size_t extra_column_bytes(PointAttribute a) {
    return extra_column_is_integer(a) ? las_extra_type_size(extra_column_integer_type(a)) : 4;
}

/// The PLY type name of `a` (uchar, ushort, uint or float).
[[nodiscard]] inline const char* extra_column_ply_type(PointAttribute a) {
    switch (extra_column_bytes(a) * (extra_column_is_integer(a) ? 1 : 0)) {
        case 1:
            return "uchar";
        case 2:
            return "ushort";
        case 4:
            return "uint";
        default:
            return "float";
    }
}

/// The bytes of all of `attributes` in a binary record.
[[nodiscard]] inline std::size_t extra_columns_bytes(std::span<const PointAttribute> attributes) {
    std::size_t n = 0;
    for (const PointAttribute a : attributes) {
        n += extra_column_bytes(a);
    }
    return n;
}

/// Writes `attributes` of `p` at `out`, little-endian (extra_columns_bytes); returns the end.
inline char* put_extra_columns(std::span<const PointAttribute> attributes, const BlockPoint& p,
                               char* out) {
    for (const PointAttribute a : attributes) {
        const double v = extra_column_value(a, p);
        switch (extra_column_is_integer(a) ? extra_column_bytes(a) : 0) {
            case 1: {
                const auto u = static_cast<std::uint8_t>(v);
                std::memcpy(out, &u, 1);
                break;
            }
            case 2: {
                const auto u = static_cast<std::uint16_t>(v);
                std::memcpy(out, &u, 2);
                break;
            }
            case 4: {
                const auto u = static_cast<std::uint32_t>(v);
                std::memcpy(out, &u, 4);
                break;
            }
            default: {
                const auto f = static_cast<float>(v);
                std::memcpy(out, &f, 4);
            }
        }
        out += extra_column_bytes(a);
    }
    return out;
}

}  // namespace beamtrace::detail
