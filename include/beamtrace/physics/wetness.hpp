// Wet and snow-covered surfaces: what rain and snow do to the materials the beam meets.
//
// Wet (after Lekner and Dorf, "Why some things are darker when wet", Appl. Opt. 27, 1988): a
// water film (n = 1.33) over a diffuse surface of albedo a. At the beam's normal incidence the
// film passes 1 - R_0 of the light (R_0 = ((n - 1) / (n + 1))^2 = 0.020); the surface scatters it
// diffusely; of that light the water-air interface lets 1 - r_i out and sends r_i back to the
// surface, r_i = 1 - (1 - r_e) / n^2 = 0.472 being the internal reflectance of diffuse light
// (total internal reflection beyond 48.8 deg; r_e = 0.066 the external reflectance of diffuse
// light). Summing the bounces:
//   a_wet = (1 - R_0) (1 - r_i) a / (1 - r_i a)
// (0.5 -> 0.34, 0.1 -> 0.054: wet surfaces are darker, the bright ones relatively less so). The
// film's own mirror reflection R_0 joins the specular lobe: s_wet = s + R_0, with an exponent of
// at least kWaterSpecularExponent (a near mirror: it returns light only near normal incidence).
// A wetness w in [0, 1] is the wetted fraction of the surface: a = (1 - w) a_dry + w a_wet and
// s = (1 - w) s_dry + w s_wet.
//
// Snow cover c in [0, 1]: that fraction of the surface is the library's snow (material_library:
// bright at 905 and 1064 nm, nearly black at 1550 nm), the rest keeps its material.
#pragma once

#include "beamtrace/physics/material.hpp"

namespace beamtrace {

/// R_0 of water at normal incidence, ((1.33 - 1) / (1.33 + 1))^2.
inline constexpr double kWaterNormalReflectance = 0.020059;
/// r_i of the header comment (1 - (1 - 0.066) / 1.33^2).
inline constexpr double kWaterInternalDiffuseReflectance = 0.47199;
/// The least specular exponent of a wet surface.
inline constexpr double kWaterSpecularExponent = 200.0;

/// a_wet of a fully wet surface of dry albedo `albedo`.
[[nodiscard]] double wet_albedo(double albedo);

/// `dry` with the wetted fraction `wetness` (in [0, 1]; 0 returns `dry` unchanged). Its albedo
/// pattern, if any, is kept and scaled the same way (reflectance only).
[[nodiscard]] Material wet_material(const Material& dry, double wetness);

/// `bare` with the fraction `cover` (in [0, 1]) under snow, at `wavelength_nm`.
[[nodiscard]] Material snow_covered_material(const Material& bare, double cover,
                                             double wavelength_nm);

}  // namespace beamtrace
