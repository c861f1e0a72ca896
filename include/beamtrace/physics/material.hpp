// Surface reflectance for LiDAR intensity and shading: a Lambertian albedo a plus a specular
// lobe of weight s and exponent n around the mirror direction, in one of two forms (Brdf):
//
//   normalized_phong (surveys' default): the energy-conserving normalised Phong BRDF
//   (Lafortune & Willems 1994; Lewis 1994)
//     f_r = a [ (1 - s) / pi + s (n + 2) / (2 pi) C^n ],   so   L = pi f_r cos i / a
//         = (1 - s) cos i + s (n + 2) / 2 C^n cos i;
//   its directional albedo (integral of f_r cos e over the viewing hemisphere) is a at normal
//   incidence and never more, and a mirror-like material (large n) flashes at the mirror angle.
//
//   phenomenological (render's default): the specular term of the "Pinholes and beachballs"
//   assignment (seeds/003)
//     L(i, e, g) = s C^n + (1 - s) cos i;
//   not energy-conserving (L = 1 at normal incidence whatever s, the lobe carries ~2s/(n+2) of
//   the energy), kept for the assignment's images.
//
// C = 2 cos i cos e - cos g is the cosine of the angle between the mirror direction of the light
// and the viewer, clamped at 0; i the incidence angle (normal vs. light), e the emittance angle
// (normal vs. viewer), g the phase angle (light vs. viewer). The brightness of a point is
// albedo * E * L under irradiance E; points with cos i <= 0 are self-shadowed and give 0.
// A monostatic LiDAR is a light at the viewer: e = i, g = 0, C = cos 2i; its L is the factor of
// the range equation (range_equation.hpp), pi f_r cos(e) / a, the same as pi f_r cos(i) / a there.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
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

/// Which form of the specular lobe a reflectance uses (the header comment).
enum class Brdf : std::uint8_t { normalized_phong, phenomenological };

/// "normalized_phong", "phenomenological".
[[nodiscard]] std::string_view to_string(Brdf brdf);
/// The BRDF named `name`; throws ConfigError listing the choices.
[[nodiscard]] Brdf parse_brdf(std::string_view name);
/// "normalized_phong | phenomenological" (help texts).
[[nodiscard]] std::string brdf_choices();

/// The normalised Phong BRDF per unit albedo, f_r / a = (1 - s) / pi + s (n + 2) / (2 pi) C^n
/// [1/sr], with C = `cos_mirror` (the cosine between the light's mirror direction and the
/// viewer) clamped at 0.
[[nodiscard]] double normalized_phong_brdf(double cos_mirror, double specular_weight,
                                           double specular_exponent);

/// The normalised Phong L(i, e, g) = pi f_r cos i / a of the header comment; 0 when cos_i <= 0.
[[nodiscard]] double normalized_phong_reflectance(double cos_i, double cos_e, double cos_g,
                                                  double specular_weight, double specular_exponent);

/// The phenomenological L(i, e, g) above (without the albedo); 0 when cos_i <= 0. C is clamped
/// at 0 before exponentiation (no negative specular lobe).
[[nodiscard]] double phenomenological_reflectance(double cos_i, double cos_e, double cos_g,
                                                  double specular_weight, double specular_exponent);

/// Monostatic case (light at the sensor): L(i, i, 0) = s cos(2i)^n + (1 - s) cos i.
[[nodiscard]] double monostatic_reflectance(double cos_incidence, double specular_weight,
                                            double specular_exponent);

/// L(i, e, g) of `brdf`.
[[nodiscard]] double reflectance(Brdf brdf, double cos_i, double cos_e, double cos_g,
                                 double specular_weight, double specular_exponent);

/// Monostatic L(i, i, 0) of `brdf`: for normalized_phong (1 - s) cos i + s (n + 2) / 2
/// cos(2i)^n cos i, for phenomenological monostatic_reflectance above.
[[nodiscard]] double monostatic_reflectance(Brdf brdf, double cos_incidence, double specular_weight,
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
