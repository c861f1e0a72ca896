// Exact ray/plane intersection for planes that are infinite or square patches.
#pragma once

#include <cmath>
#include <limits>
#include <optional>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// A plane through `point_m` with unit `normal`, optionally bounded to the square
/// |(x - point)·u| <= half_size, |(x - point)·w| <= half_size with w = normal × u.
struct PlanePatch {
    Vec3d point_m{0, 0, 0};
    Vec3d normal{0, 0, 1};  ///< unit length
    Vec3d u_axis{1, 0, 0};  ///< unit, perpendicular to normal
    double half_size_m = std::numeric_limits<double>::infinity();

    [[nodiscard]] Vec3d w_axis() const { return cross(normal, u_axis); }
};

/// The in-plane axis u that `make_square` uses for a normal (any unit vector perpendicular to
/// it, chosen the same way so analytic and triangulated squares coincide).
[[nodiscard]] inline Vec3d plane_u_axis(const Vec3d& unit_normal) {
    const Vec3d helper = std::fabs(unit_normal.z) < 0.9 ? Vec3d{0, 0, 1} : Vec3d{1, 0, 0};
    return normalize(cross(helper, unit_normal));
}

/// A square patch of side `size_m` (infinite for +inf) centred on `point_m`, exactly the square
/// of `make_square(point_m, normal, size_m)`.
[[nodiscard]] inline PlanePatch make_plane_patch(const Vec3d& point_m, const Vec3d& normal,
                                                 double size_m) {
    const Vec3d n = normalize(normal);
    return {point_m, n, plane_u_axis(n), 0.5 * size_m};
}

/// t in [tmin, tmax] where the ray o + t d meets the plane (inside the patch), or nothing. Rays
/// parallel to the plane miss.
[[nodiscard]] inline std::optional<double> intersect_plane(const Vec3d& o, const Vec3d& d,
                                                           const PlanePatch& p, double tmin,
                                                           double tmax) {
    const double denom = dot(p.normal, d);
    if (denom == 0.0) {
        return std::nullopt;
    }
    const double t = dot(p.normal, p.point_m - o) / denom;
    if (!(t >= tmin && t <= tmax)) {
        return std::nullopt;
    }
    if (std::isfinite(p.half_size_m)) {
        const Vec3d r = o + d * t - p.point_m;
        if (std::fabs(dot(r, p.u_axis)) > p.half_size_m ||
            std::fabs(dot(r, p.w_axis())) > p.half_size_m) {
            return std::nullopt;
        }
    }
    return t;
}

}  // namespace beamtrace
