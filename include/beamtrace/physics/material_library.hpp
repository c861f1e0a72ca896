// A small library of named materials with typical reflectances at the common LiDAR wavelengths
// (905 nm, 1064 nm, 1550 nm).
//
// Where the numbers come from: they are TYPICAL, rounded values read off published spectral
// reflectance curves (the ECOSTRESS/ASTER and USGS splib07 spectral libraries: asphalt, concrete,
// green grass and leaves, conifer needles, dry soil, snow, water, paints and metals) and
// consistent with the ranges quoted in the LiDAR radiometric-calibration literature (e.g. Kashani
// et al., Sensors 15 (2015) 28099). Real surfaces vary by +/- 30 % or more with moisture, age
// and roughness; use them as plausible defaults, not as measurements. Notable wavelength effects
// they reproduce: vegetation is bright in the near infrared (the "red edge" plateau) but darker at
// 1550 nm (leaf water absorption), snow and ice are nearly black at 1550 nm.
// Specular weights/exponents are plausible values for the phenomenological model, not fits.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "beamtrace/physics/material.hpp"

namespace beamtrace {

struct NamedMaterial {
    std::string_view name;
    double reflectance_905nm;
    double reflectance_1064nm;
    double reflectance_1550nm;
    double specular_weight;
    double specular_exponent;
    std::string_view note;  ///< what it stands for
};

/// Every entry of the library (asphalt, concrete, grass, vegetation, conifer, soil, snow, water,
/// metal, white_paint, car_paint, brick, wood, glass).
[[nodiscard]] std::span<const NamedMaterial> material_library();

/// Reflectance of `m` at `wavelength_nm`: linear between the three tabulated wavelengths,
/// constant beyond them.
[[nodiscard]] double reflectance_at(const NamedMaterial& m, double wavelength_nm);

/// The library material `name` at `wavelength_nm` as a Material; nullopt for unknown names.
[[nodiscard]] std::optional<Material> library_material(std::string_view name, double wavelength_nm);

/// "asphalt, concrete, ..." (for error messages).
[[nodiscard]] std::string material_library_names();

}  // namespace beamtrace
