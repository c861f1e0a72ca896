// Lights and the reflectance model of the "Pinholes and beachballs" assignment (seed 003):
// brightness = albedo * E * [s * C^n + (1 - s) * cos i], C = 2 cos i cos e - cos g, zero where
// cos i <= 0 (self-shadowed), plus an ambient term.
#pragma once

#include <cmath>
#include <cstdint>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/scene/surface_pattern.hpp"

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

/// The assignment's L(i, e, g) = s C^n + (1 - s) cos i with C = 2 cos i cos e - cos g (the cosine
/// between the mirror direction of the light and the view direction, clamped at 0); 0 when
/// cos i <= 0. Multiply by the albedo and the irradiance.
[[nodiscard]] inline double phenomenological_reflectance(double cos_i, double cos_e, double cos_g,
                                                         double s, double n) {
    if (!(cos_i > 0.0)) {
        return 0.0;
    }
    const double c = 2.0 * cos_i * cos_e - cos_g;
    const double spec = c > 0.0 ? std::pow(c, n) : 0.0;
    return s * spec + (1.0 - s) * cos_i;
}

/// Albedo of a pattern at a point of a sphere with unit normal `local_n` in the sphere's frame.
[[nodiscard]] double sphere_albedo(const SurfacePattern& p, double base, const Vec3d& local_n);
/// Albedo of a pattern at in-plane coordinates (a, b) metres (planes: along u and w).
[[nodiscard]] double planar_albedo(const SurfacePattern& p, double base, double a_m, double b_m);
/// Albedo of a pattern at a world point of a triangle mesh (stripes along x, 3-D checker).
[[nodiscard]] double solid_albedo(const SurfacePattern& p, double base, const Vec3d& x_m);

}  // namespace beamtrace
