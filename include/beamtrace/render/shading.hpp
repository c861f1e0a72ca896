// Lights for the reflectance model of the "Pinholes and beachballs" assignment (seed 003):
// brightness = albedo * E * [s * C^n + (1 - s) * cos i], C = 2 cos i cos e - cos g, zero where
// cos i <= 0 (self-shadowed), plus an ambient term. The model itself, the albedo patterns and the
// colour are the physics Material's (physics/material.hpp): the one material model of `render`
// and surveys.
#pragma once

#include <cmath>
#include <cstdint>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/physics/material.hpp"

namespace beamtrace {

enum class LightKind : std::uint8_t { directional, point };

struct Light {
    LightKind kind = LightKind::directional;
    /// Directional: unit vector from the scene towards the light (constant everywhere).
    Vec3d direction{0, 0, 1};
    /// Point: position of the light, metres.
    Vec3d position_m{0, 0, 0};
    /// Directional: irradiance E on a surface facing the light. Point: "power" P, giving
    /// E = P / r^2 at distance r (inverse-square falloff).
    double intensity = 1.0;
};

/// A directional light from azimuth `az_rad` (counter-clockwise from +x towards +y, seen from
/// above) and elevation `el_rad` above the horizontal.
[[nodiscard]] inline Light directional_light(double az_rad, double el_rad, double intensity = 1.0) {
    return {LightKind::directional,
            {std::cos(el_rad) * std::cos(az_rad), std::cos(el_rad) * std::sin(az_rad),
             std::sin(el_rad)},
            {0, 0, 0},
            intensity};
}

[[nodiscard]] inline Light point_light(const Vec3d& position_m, double power) {
    return {LightKind::point, {0, 0, 1}, position_m, power};
}

}  // namespace beamtrace
