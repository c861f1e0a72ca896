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

namespace beamtrace {

/// Procedural albedo patterns (the beach ball's stripes, a checkerboard).
enum class AlbedoPatternKind : std::uint8_t {
    uniform,  ///< the material's reflectance everywhere
    stripes,  ///< slabs of width period_m / 2 across `axis`, alternating reflectance/alternate
    checker,  ///< cubes of side period_m / 2 (a 3-D checkerboard: a checker on any plane)
    sectors,  ///< `sectors` wedges around `axis` through `center_m` (beach-ball gores)
};

struct AlbedoPattern {
    AlbedoPatternKind kind = AlbedoPatternKind::uniform;
    double alternate_reflectance = 0.1;  ///< albedo of the odd stripes/cells/wedges, [0, 1]
    double period_m = 1.0;               ///< stripes/checker: one even + one odd cell, > 0
    Vec3d axis{0, 0, 1};                 ///< stripes: across this; sectors: around it
    Vec3d center_m{0, 0, 0};             ///< sectors: a point on the axis
    int sectors = 6;                     ///< sectors: number of wedges (even, >= 2)
};

/// Optical properties of one material. Reflectances are albedos at the laser wavelength.
struct Material {
    std::string name = "default";
    double reflectance = 0.5;         ///< Lambertian albedo a, [0, 1]
    double specular_weight = 0.0;     ///< s, [0, 1]
    double specular_exponent = 10.0;  ///< n, > 0
    AlbedoPattern pattern;            ///< optional albedo pattern (default uniform)

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

/// The albedo of `m` at world point `point_m` (its pattern evaluated there).
[[nodiscard]] double albedo(const Material& m, const Vec3d& point_m);

/// The albedo of `m` at surface coordinates (u, v): stripes across u, checker on (u, v),
/// sectors over u in [0, 1) (u = longitude / 2 pi); the pattern's period is in units of u, v.
[[nodiscard]] double albedo_uv(const Material& m, double u, double v);

}  // namespace beamtrace
