#include "beamtrace/physics/material.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "beamtrace/core/name_table.hpp"

namespace beamtrace {
namespace {

constexpr NameTable<Brdf, 2> kBrdfs{
    "brdf",
    {{{Brdf::normalized_phong, "normalized_phong"}, {Brdf::phenomenological, "phenomenological"}}}};

bool unit_interval(double v) {
    return v >= 0.0 && v <= 1.0;
}

}  // namespace

std::string_view to_string(Brdf brdf) {
    return kBrdfs.to_string(brdf);
}

Brdf parse_brdf(std::string_view name) {
    return kBrdfs.parse(name);
}

std::string brdf_choices() {
    return std::string(kBrdfs.choices());
}

std::vector<std::string> Material::validate() const {
    std::vector<std::string> p;
    const std::string who = "material '" + name + "': ";
    if (!unit_interval(reflectance)) {
        p.push_back(who + "reflectance must be in [0, 1]");
    }
    if (!unit_interval(specular_weight)) {
        p.push_back(who + "specular_weight must be in [0, 1]");
    }
    if (!(specular_exponent > 0) || !std::isfinite(specular_exponent)) {
        p.push_back(who + "specular_exponent must be positive");
    }
    if (pattern.kind != AlbedoPatternKind::uniform) {
        if (!unit_interval(pattern.alternate_reflectance)) {
            p.push_back(who + "pattern reflectance must be in [0, 1]");
        }
        if (!(pattern.size_m > 0) || !std::isfinite(pattern.size_m)) {
            p.push_back(who + "pattern size_m must be positive");
        }
        if (pattern.count < 2) {
            p.push_back(who + "pattern count must be at least 2");
        }
    }
    if (!unit_interval(color.x) || !unit_interval(color.y) || !unit_interval(color.z)) {
        p.push_back(who + "color channels must be in [0, 1]");
    }
    return p;
}

double phenomenological_reflectance(double cos_i, double cos_e, double cos_g,
                                    double specular_weight, double specular_exponent) {
    if (!(cos_i > 0.0)) {
        return 0.0;  // self-shadowed
    }
    double lobe = 0.0;
    if (specular_weight > 0.0) {
        const double c = 2.0 * cos_i * cos_e - cos_g;
        lobe = c > 0.0 ? std::pow(std::min(c, 1.0), specular_exponent) : 0.0;
    }
    return specular_weight * lobe + (1.0 - specular_weight) * cos_i;
}

namespace {

/// pi f_r / a of the normalised Phong BRDF: (1 - s) + s (n + 2) / 2 C^n (exactly 1 for s = 0).
double phong_factor(double cos_mirror, double specular_weight, double specular_exponent) {
    double lobe = 0.0;
    if (specular_weight > 0.0 && cos_mirror > 0.0) {
        lobe = (specular_exponent + 2.0) / 2.0 *
               std::pow(std::min(cos_mirror, 1.0), specular_exponent);
    }
    return (1.0 - specular_weight) + specular_weight * lobe;
}

}  // namespace

double normalized_phong_brdf(double cos_mirror, double specular_weight, double specular_exponent) {
    return phong_factor(cos_mirror, specular_weight, specular_exponent) / std::numbers::pi;
}

double normalized_phong_reflectance(double cos_i, double cos_e, double cos_g,
                                    double specular_weight, double specular_exponent) {
    if (!(cos_i > 0.0)) {
        return 0.0;  // self-shadowed
    }
    const double c = 2.0 * cos_i * cos_e - cos_g;
    return phong_factor(c, specular_weight, specular_exponent) * cos_i;
}

double reflectance(Brdf brdf, double cos_i, double cos_e, double cos_g, double specular_weight,
                   double specular_exponent) {
    return brdf == Brdf::normalized_phong
               ? normalized_phong_reflectance(cos_i, cos_e, cos_g, specular_weight,
                                              specular_exponent)
               : phenomenological_reflectance(cos_i, cos_e, cos_g, specular_weight,
                                              specular_exponent);
}

double monostatic_reflectance(Brdf brdf, double cos_incidence, double specular_weight,
                              double specular_exponent) {
    return reflectance(brdf, cos_incidence, cos_incidence, 1.0, specular_weight, specular_exponent);
}

double monostatic_reflectance(double cos_incidence, double specular_weight,
                              double specular_exponent) {
    return phenomenological_reflectance(cos_incidence, cos_incidence, 1.0, specular_weight,
                                        specular_exponent);
}

double phenomenological_reflectance(const Material& m, const Vec3d& normal, const Vec3d& to_light,
                                    const Vec3d& to_viewer) {
    return phenomenological_reflectance(dot(normal, to_light), dot(normal, to_viewer),
                                        dot(to_viewer, to_light), m.specular_weight,
                                        m.specular_exponent);
}

double albedo(const Material& m, const PatternFrame& frame, const Vec3d& point_m) {
    return in_alternate_cell(m.pattern, frame, point_m) ? m.pattern.alternate_reflectance
                                                        : m.reflectance;
}

double albedo(const Material& m, const Vec3d& point_m) {
    return albedo(m, PatternFrame{}, point_m);
}

}  // namespace beamtrace
