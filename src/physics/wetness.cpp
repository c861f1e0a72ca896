#include "beamtrace/physics/wetness.hpp"

#include <algorithm>

#include "beamtrace/physics/material_library.hpp"

namespace beamtrace {

double wet_albedo(double albedo) {
    constexpr double r_i = kWaterInternalDiffuseReflectance;
    return (1.0 - kWaterNormalReflectance) * (1.0 - r_i) * albedo / (1.0 - r_i * albedo);
}

namespace {

double wetted(double dry, double wetness) {
    return (1.0 - wetness) * dry + wetness * wet_albedo(dry);
}

}  // namespace

Material wet_material(const Material& dry, double wetness) {
    const double w = std::clamp(wetness, 0.0, 1.0);
    if (w == 0.0) {
        return dry;
    }
    Material m = dry;
    m.reflectance = wetted(dry.reflectance, w);
    m.pattern.alternate_reflectance = wetted(dry.pattern.alternate_reflectance, w);
    m.specular_weight = std::min(1.0, dry.specular_weight + w * kWaterNormalReflectance);
    m.specular_exponent = std::max(dry.specular_exponent, kWaterSpecularExponent);
    return m;
}

Material snow_covered_material(const Material& bare, double cover, double wavelength_nm) {
    const double c = std::clamp(cover, 0.0, 1.0);
    if (c == 0.0) {
        return bare;
    }
    const Material snow = library_material("snow", wavelength_nm).value_or(bare);
    Material m = bare;
    m.reflectance = (1.0 - c) * bare.reflectance + c * snow.reflectance;
    m.pattern.alternate_reflectance =
        (1.0 - c) * bare.pattern.alternate_reflectance + c * snow.reflectance;
    m.specular_weight = (1.0 - c) * bare.specular_weight + c * snow.specular_weight;
    if (c >= 0.5) {
        m.specular_exponent = snow.specular_exponent;
    }
    return m;
}

}  // namespace beamtrace
