#include "beamtrace/render/shading.hpp"

#include <cmath>
#include <numbers>

namespace beamtrace {
namespace {

bool odd(double k) {
    return std::fmod(std::fabs(k), 2.0) == 1.0;
}

}  // namespace

double sphere_albedo(const SurfacePattern& p, double base, const Vec3d& local_n) {
    if (p.kind == SurfacePatternKind::none) {
        return base;
    }
    const double pi = std::numbers::pi;
    const double lon = std::atan2(local_n.y, local_n.x) + pi;  // [0, 2 pi]
    const double k_lon = std::floor(lon / (2.0 * pi) * p.count);
    double k = k_lon;
    if (p.kind == SurfacePatternKind::checker) {
        const double lat = std::asin(std::fmax(-1.0, std::fmin(1.0, local_n.z))) + 0.5 * pi;
        const int bands = p.count / 2 > 1 ? p.count / 2 : 1;
        k += std::floor(lat / pi * bands);
    }
    return odd(k) ? p.reflectance : base;
}

double planar_albedo(const SurfacePattern& p, double base, double a_m, double b_m) {
    if (p.kind == SurfacePatternKind::none) {
        return base;
    }
    double k = std::floor(a_m / p.size_m);
    if (p.kind == SurfacePatternKind::checker) {
        k += std::floor(b_m / p.size_m);
    }
    return odd(k) ? p.reflectance : base;
}

double solid_albedo(const SurfacePattern& p, double base, const Vec3d& x_m) {
    if (p.kind == SurfacePatternKind::none) {
        return base;
    }
    double k = std::floor(x_m.x / p.size_m);
    if (p.kind == SurfacePatternKind::checker) {
        k += std::floor(x_m.y / p.size_m) + std::floor(x_m.z / p.size_m);
    }
    return odd(k) ? p.reflectance : base;
}

}  // namespace beamtrace
