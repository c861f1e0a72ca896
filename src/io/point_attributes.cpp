#include "beamtrace/io/point_attributes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

namespace beamtrace {

namespace {

struct Entry {
    PointAttribute attribute;
    std::string_view key;
    LasExtraType type;
    const char* name;
    double scale;  ///< 1: unscaled
    const char* description;
};

constexpr std::array<Entry, 10> kEntries{{
    {PointAttribute::range, "range", LasExtraType::u32, "range_m", 0.001,
     "range from beam origin, m"},
    {PointAttribute::incidence_angle, "incidence_angle", LasExtraType::u16, "incidence_angle_deg",
     0.01, "beam to surface normal, deg"},
    {PointAttribute::echo_width, "echo_width", LasExtraType::u16, "echo_width_ns", 0.01,
     "echo FWHM, ns"},
    {PointAttribute::beam, "beam", LasExtraType::u16, "beam", 1.0, "scanner channel (row)"},
    {PointAttribute::object_id, "object_id", LasExtraType::u32, "object_id", 1.0,
     "scene part_id of the hit"},
    {PointAttribute::instance_id, "instance_id", LasExtraType::u32, "instance_id", 1.0,
     "scene object (copy) hit"},
    {PointAttribute::velocity_x, "velocity_x", LasExtraType::f32, "velocity_x", 1.0,
     "hit object velocity x, m/s"},
    {PointAttribute::velocity_y, "velocity_y", LasExtraType::f32, "velocity_y", 1.0,
     "hit object velocity y, m/s"},
    {PointAttribute::velocity_z, "velocity_z", LasExtraType::f32, "velocity_z", 1.0,
     "hit object velocity z, m/s"},
    {PointAttribute::weather, "weather", LasExtraType::u8, "weather", 1.0,
     "0 scene 1 fog 2 rain 3 snow"},
}};

const Entry& entry(PointAttribute a) {
    return kEntries.at(static_cast<std::size_t>(a));
}

/// The no-data value of echo_width_ns (its type's largest).
constexpr std::uint16_t kNoEchoWidth = 65535;

template <class T>
void put(std::uint8_t*& out, double raw) {
    constexpr double top = static_cast<double>(std::numeric_limits<T>::max());
    const T v = static_cast<T>(std::clamp(std::round(raw), 0.0, top));
    std::memcpy(out, &v, sizeof(T));
    out += sizeof(T);
}

double value(PointAttribute a, const PointAttributeValues& v) {
    switch (a) {
        case PointAttribute::range:
            return v.range_m;
        case PointAttribute::incidence_angle:
            return v.incidence_deg;
        case PointAttribute::echo_width:
            return v.echo_width_ns;
        case PointAttribute::beam:
            return v.beam;
        case PointAttribute::object_id:
            return v.object_id;
        case PointAttribute::instance_id:
            return v.instance_id;
        case PointAttribute::velocity_x:
            return v.velocity_mps.x;
        case PointAttribute::velocity_y:
            return v.velocity_mps.y;
        case PointAttribute::velocity_z:
            return v.velocity_mps.z;
        case PointAttribute::weather:
            return v.weather;
    }
    return 0.0;
}

}  // namespace

std::string_view point_attribute_key(PointAttribute a) {
    return entry(a).key;
}

std::optional<PointAttribute> point_attribute_named(std::string_view key) {
    for (const Entry& e : kEntries) {
        if (e.key == key) {
            return e.attribute;
        }
    }
    return std::nullopt;
}

std::string point_attribute_keys() {
    std::string out;
    for (const Entry& e : kEntries) {
        out += (out.empty() ? "" : ", ") + std::string(e.key);
    }
    return out;
}

LasExtraBytesDescriptor point_attribute_descriptor(PointAttribute a) {
    const Entry& e = entry(a);
    LasExtraBytesDescriptor d;
    d.data_type = e.type;
    d.name = e.name;
    d.description = e.description;
    if (e.scale != 1.0) {
        d.options |= LasExtraBytesDescriptor::kScale;
        d.scale = e.scale;
    }
    if (a == PointAttribute::echo_width) {
        d.options |= LasExtraBytesDescriptor::kNoData;
        d.no_data = kNoEchoWidth;
    }
    return d;
}

void encode_point_attributes(std::span<const PointAttribute> attributes,
                             const PointAttributeValues& v, std::uint8_t* out) {
    for (const PointAttribute a : attributes) {
        const Entry& e = entry(a);
        double raw = value(a, v) / e.scale;
        if (a == PointAttribute::echo_width) {
            // The largest value is the no-data value: real widths stop one step below it.
            raw = std::isfinite(raw) ? std::min(raw, kNoEchoWidth - 1.0) : double{kNoEchoWidth};
        }
        if (e.type == LasExtraType::f32) {
            const auto f = static_cast<float>(value(a, v));
            std::memcpy(out, &f, sizeof(float));
            out += sizeof(float);
        } else if (e.type == LasExtraType::u16) {
            put<std::uint16_t>(out, raw);
        } else {
            put<std::uint32_t>(out, raw);
        }
    }
}

}  // namespace beamtrace
