// Per-point attributes a survey can add to points.las / points.laz as LAS 1.4 extra bytes
// (`output: {extra_bytes: [...]}`, docs/survey.md): their survey names, and the name, type,
// scale and no-data value of each in the Extra Bytes VLR (docs/formats.md).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/io/las_extra_bytes.hpp"

namespace beamtrace {

/// What an extra-bytes field of a point holds.
enum class PointAttribute : std::uint8_t {
    range,            ///< range_m: the return's range from the beam origin, uint32 x 0.001 m
    incidence_angle,  ///< incidence_angle_deg: beam to surface normal, uint16 x 0.01 deg
    echo_width,       ///< echo_width_ns: the echo's FWHM, uint16 x 0.01 ns (no physics: no-data)
    beam,             ///< beam: the scanner channel (row), uint16
    object_id,        ///< object_id: the hit scene part's part_id, uint32
    instance_id,      ///< instance_id: the hit object (Scene::object_of_face), uint32
    velocity_x,       ///< velocity_x: the hit surface point's velocity along x, float32 m/s
    velocity_y,       ///< velocity_y: the same along y
    velocity_z,       ///< velocity_z: the same along z
    weather,          ///< weather: what made the echo (0 the scene, 1 fog, 2 rain, 3 snow), uint8
};

/// The survey name (`range`, `incidence_angle`, `echo_width`, `beam`, `object_id`,
/// `instance_id`, `velocity_x`, `velocity_y`, `velocity_z`, `weather`).
[[nodiscard]] std::string_view point_attribute_key(PointAttribute a);
/// The attribute of survey name `key`, or none.
[[nodiscard]] std::optional<PointAttribute> point_attribute_named(std::string_view key);
/// Every survey name, comma-separated (error messages).
[[nodiscard]] std::string point_attribute_keys();

/// The descriptor of `a` in the Extra Bytes VLR (its LAS name, type, scale, no-data).
[[nodiscard]] LasExtraBytesDescriptor point_attribute_descriptor(PointAttribute a);

/// The raw values of a point's attributes, before encoding.
struct PointAttributeValues {
    double range_m = 0.0;
    double incidence_deg = 0.0;
    double echo_width_ns = 0.0;  ///< not finite: unknown (written as the no-data value)
    std::uint32_t beam = 0;
    std::uint32_t object_id = 0;
    std::uint32_t instance_id = 0;
    Vec3d velocity_mps{0, 0, 0};
    std::uint8_t weather = 0;
};

/// Writes `attributes`' fields of `v`, in order, little-endian, at `out` (their descriptors'
/// sizes summed: las_extra_bytes_size). Integer values are rounded to the scale and clamped to the
/// type; float32 ones are written as they are.
void encode_point_attributes(std::span<const PointAttribute> attributes,
                             const PointAttributeValues& v, std::uint8_t* out);

}  // namespace beamtrace
