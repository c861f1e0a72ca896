#include "beamtrace/physics/albedo_pattern.hpp"

#include <cmath>
#include <numbers>

namespace beamtrace {
namespace {

bool odd(double k) {
    return std::fmod(std::fabs(k), 2.0) == 1.0;
}

/// Cell index on a sphere from the unit normal in its local frame.
double sphere_cell(const AlbedoPattern& p, const Vec3d& local_n) {
    const double pi = std::numbers::pi;
    const double lon = std::atan2(local_n.y, local_n.x) + pi;  // [0, 2 pi]
    double k = std::floor(lon / (2.0 * pi) * p.count);
    if (p.kind == AlbedoPatternKind::checker) {
        const double lat = std::asin(std::fmax(-1.0, std::fmin(1.0, local_n.z))) + 0.5 * pi;
        const int bands = p.count / 2 > 1 ? p.count / 2 : 1;
        k += std::floor(lat / pi * bands);
    }
    return k;
}

/// Cell index at in-plane coordinates (a, b) metres.
double plane_cell(const AlbedoPattern& p, double a_m, double b_m) {
    double k = std::floor(a_m / p.size_m);
    if (p.kind == AlbedoPatternKind::checker) {
        k += std::floor(b_m / p.size_m);
    }
    return k;
}

/// Cell index at a point of a solid (scene coordinates).
double solid_cell(const AlbedoPattern& p, const Vec3d& x_m) {
    double k = std::floor(x_m.x / p.size_m);
    if (p.kind == AlbedoPatternKind::checker) {
        k += std::floor(x_m.y / p.size_m) + std::floor(x_m.z / p.size_m);
    }
    return k;
}

/// The cell index as a double (exact for any cell a scene reaches).
double cell_of(const AlbedoPattern& pattern, const PatternFrame& frame, const Vec3d& point_m) {
    switch (frame.surface) {
        case PatternSurface::sphere: {
            const Vec3d n = (point_m - frame.origin_m) * (1.0 / frame.radius_m);
            return sphere_cell(pattern, frame.attitude.conjugate().rotate(n));
        }
        case PatternSurface::plane: {
            const Vec3d r = point_m - frame.origin_m;
            return plane_cell(pattern, dot(r, frame.u_axis), dot(r, frame.w_axis));
        }
        case PatternSurface::solid:
            break;
    }
    return solid_cell(pattern, point_m);
}

}  // namespace

std::int64_t pattern_cell(const AlbedoPattern& pattern, const PatternFrame& frame,
                          const Vec3d& point_m) {
    if (pattern.kind == AlbedoPatternKind::uniform) {
        return 0;
    }
    const double k = cell_of(pattern, frame, point_m);
    return std::isfinite(k) && std::fabs(k) < 1e18 ? static_cast<std::int64_t>(k) : 0;
}

Vec3d pattern_color(const AlbedoPattern& pattern, const PatternFrame& frame, const Vec3d& point_m,
                    const Vec3d& base) {
    if (pattern.colors.empty()) {
        return base;
    }
    const auto n = static_cast<std::int64_t>(pattern.colors.size());
    const std::int64_t k = ((pattern_cell(pattern, frame, point_m) % n) + n) % n;
    return pattern.colors[static_cast<std::size_t>(k)];
}

bool in_alternate_cell(const AlbedoPattern& pattern, const PatternFrame& frame,
                       const Vec3d& point_m) {
    if (pattern.kind == AlbedoPatternKind::uniform) {
        return false;
    }
    return odd(cell_of(pattern, frame, point_m));
}

}  // namespace beamtrace
