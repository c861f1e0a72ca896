// output.extra_bytes in the text and binary point files (CSV, PLY, PCD): the attributes of
// io/point_attributes.hpp as columns / properties named as their LAS extra-bytes dimensions
// (range_m, incidence_angle_deg, echo_width_ns, beam, object_id), in the order listed.
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

/// Whether `a` is an integer (beam, object_id) rather than a measurement.
[[nodiscard]] inline bool extra_column_is_integer(PointAttribute a) {
    return a == PointAttribute::beam || a == PointAttribute::object_id;
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
    }
    return 0.0;
}

/// Bytes of `a` in a binary record: float32 measurements, uint16 beam, uint32 object_id.
[[nodiscard]] inline std::size_t extra_column_bytes(PointAttribute a) {
    return a == PointAttribute::beam ? 2 : 4;
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
        if (a == PointAttribute::beam) {
            const auto u = static_cast<std::uint16_t>(v);
            std::memcpy(out, &u, 2);
        } else if (a == PointAttribute::object_id) {
            const auto u = static_cast<std::uint32_t>(v);
            std::memcpy(out, &u, 4);
        } else {
            const auto f = static_cast<float>(v);
            std::memcpy(out, &f, 4);
        }
        out += extra_column_bytes(a);
    }
    return out;
}

}  // namespace beamtrace::detail
