#include "beamtrace/physics/material.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace beamtrace {
namespace {

bool unit_interval(double v) {
    return v >= 0.0 && v <= 1.0;
}

/// 0 for even cells, 1 for odd ones (floor works for negative coordinates too).
int parity(double x) {
    const auto k = static_cast<long long>(std::floor(x));
    return static_cast<int>(((k % 2) + 2) % 2);
}

double pick(const Material& m, int odd) {
    return odd != 0 ? m.pattern.alternate_reflectance : m.reflectance;
}

}  // namespace

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
            p.push_back(who + "pattern alternate_reflectance must be in [0, 1]");
        }
        if (!(pattern.period_m > 0) || !std::isfinite(pattern.period_m)) {
            p.push_back(who + "pattern period_m must be positive");
        }
        if (!(length(pattern.axis) > 0)) {
            p.push_back(who + "pattern axis must not be zero");
        }
        if (pattern.kind == AlbedoPatternKind::sectors &&
            (pattern.sectors < 2 || pattern.sectors % 2 != 0)) {
            p.push_back(who + "pattern sectors must be even and at least 2");
        }
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

double albedo(const Material& m, const Vec3d& point_m) {
    const AlbedoPattern& pat = m.pattern;
    const double half = pat.period_m / 2.0;
    switch (pat.kind) {
        case AlbedoPatternKind::uniform:
            return m.reflectance;
        case AlbedoPatternKind::stripes:
            return pick(m, parity(dot(point_m, normalize(pat.axis)) / half));
        case AlbedoPatternKind::checker:
            return pick(m, (parity(point_m.x / half) + parity(point_m.y / half) +
                            parity(point_m.z / half)) %
                               2);
        case AlbedoPatternKind::sectors: {
            // Longitude of the point around the axis, measured in a fixed basis.
            const Vec3d a = normalize(pat.axis);
            const Vec3d helper = std::abs(a.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
            const Vec3d e1 = normalize(cross(a, helper));
            const Vec3d e2 = cross(a, e1);
            const Vec3d d = point_m - pat.center_m;
            const double lon = std::atan2(dot(d, e2), dot(d, e1));  // (-pi, pi]
            const double u = (lon + std::numbers::pi) / (2.0 * std::numbers::pi);
            return albedo_uv(m, u, 0.0);
        }
    }
    return m.reflectance;
}

double albedo_uv(const Material& m, double u, double v) {
    const AlbedoPattern& pat = m.pattern;
    const double half = pat.period_m / 2.0;
    switch (pat.kind) {
        case AlbedoPatternKind::uniform:
            return m.reflectance;
        case AlbedoPatternKind::stripes:
            return pick(m, parity(u / half));
        case AlbedoPatternKind::checker:
            return pick(m, (parity(u / half) + parity(v / half)) % 2);
        case AlbedoPatternKind::sectors:
            return pick(m, parity(u * static_cast<double>(pat.sectors)));
    }
    return m.reflectance;
}

}  // namespace beamtrace
