// Surface reflectance for LiDAR intensity and shading: Lambertian albedo plus the
// phenomenological specular term of the "Pinholes and beachballs" assignment (seeds/003),
//   L(i, e, g) = s C^n + (1 - s) cos i,   C = 2 cos i cos e - cos g,
// with i the incidence angle (normal vs. light), e the emittance angle (normal vs. viewer), g
// the phase angle (light vs. viewer), s the specular weight and n the exponent. The brightness
// of a point is albedo * L; points with cos i <= 0 are self-shadowed and give 0.
// A monostatic LiDAR is a light at the viewer: e = i, g = 0, C = cos 2i.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/physics/albedo_pattern.hpp"

namespace beamtrace {

/// Optical properties of one material: the one material model of scene files, `render` and
/// surveys (docs/scene-file.md). Reflectances are albedos at the laser wavelength.
struct Material {
    std::string name = "default";
    double reflectance = 0.5;         ///< Lambertian albedo a, [0, 1]
    double specular_weight = 0.0;     ///< s, [0, 1]
    double specular_exponent = 10.0;  ///< n, > 0
    AlbedoPattern pattern;            ///< optional albedo pattern (default uniform)
    /// A named material of the physics library (material_library.hpp) whose reflectance and
    /// specular term replace the three numbers above once resolved at a wavelength
    /// (resolve_library_material); empty: none.
    std::string library;
    /// Linear RGB tint of `render`'s images (each channel times the shaded brightness), [0, 1];
    /// no effect on LiDAR intensities.
    Vec3d color{1, 1, 1};

    /// Every problem with these settings ("reflectance must be in [0, 1]", ...); empty if valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// The phenomenological L(i, e, g) above (without the albedo); 0 when cos_i <= 0. C is clamped
/// at 0 before exponentiation (no negative specular lobe).
[[nodiscard]] double phenomenological_reflectance(double cos_i, double cos_e, double cos_g,
                                                  double specular_weight, double specular_exponent);

/// Monostatic case (light at the sensor): L(i, i, 0) = s cos(2i)^n + (1 - s) cos i.
[[nodiscard]] double monostatic_reflectance(double cos_incidence, double specular_weight,
                                            double specular_exponent);

/// The bistatic L for unit vectors: `normal`, `to_light` and `to_viewer` from the surface point.
[[nodiscard]] double phenomenological_reflectance(const Material& m, const Vec3d& normal,
                                                  const Vec3d& to_light, const Vec3d& to_viewer);

/// The albedo of `m` at `point_m` on the surface `frame`: its reflectance, or the pattern's
/// alternate reflectance in the pattern's odd cells.
[[nodiscard]] double albedo(const Material& m, const PatternFrame& frame, const Vec3d& point_m);

/// The same on a solid (the pattern in scene coordinates).
[[nodiscard]] double albedo(const Material& m, const Vec3d& point_m);

}  // namespace beamtrace
