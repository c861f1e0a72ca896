// Exact ray/sphere intersection (the assignment's analytic primitive) and chord lengths.
#pragma once

#include <cmath>
#include <optional>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct Sphere {
    Vec3d center_m{0, 0, 0};
    double radius_m = 1.0;
};

/// Where a line meets a sphere: entry and exit parameters, t_enter <= t_exit (either may be
/// negative: the sphere is behind or around the ray origin).
struct SphereInterval {
    double t_enter = 0.0;
    double t_exit = 0.0;
};

/// The two roots of |o + t d - c|^2 = r^2 (d need not be unit length), or nothing when the line
/// misses (a tangent line gives t_enter == t_exit). Uses the numerically stable form of Ray
/// Tracing Gems ch. 7: the discriminant from the closest approach, the second root from the
/// product of the roots.
[[nodiscard]] inline std::optional<SphereInterval> intersect_sphere_line(const Vec3d& o,
                                                                         const Vec3d& d,
                                                                         const Sphere& s) {
    const Vec3d f = o - s.center_m;
    const double a = dot(d, d);
    if (!(a > 0.0)) {
        return std::nullopt;
    }
    const double b = -dot(f, d);  // t of the closest approach times a
    const Vec3d closest = f + d * (b / a);
    const double r2 = s.radius_m * s.radius_m;
    const double disc = a * (r2 - dot(closest, closest));
    if (disc < 0.0) {
        return std::nullopt;
    }
    const double c = dot(f, f) - r2;
    const double q = b + std::copysign(std::sqrt(disc), b);
    double t0 = 0.0, t1 = 0.0;
    if (q == 0.0) {
        t0 = t1 = 0.0;  // origin on the sphere at the closest approach
    } else {
        t0 = c / q;
        t1 = q / a;
    }
    if (t0 > t1) {
        std::swap(t0, t1);
    }
    return SphereInterval{t0, t1};
}

/// Nearest t in [tmin, tmax] where the ray meets the sphere's surface, or nothing.
[[nodiscard]] inline std::optional<double> intersect_sphere(const Vec3d& o, const Vec3d& d,
                                                            const Sphere& s, double tmin,
                                                            double tmax) {
    const auto iv = intersect_sphere_line(o, d, s);
    if (!iv) {
        return std::nullopt;
    }
    if (iv->t_enter >= tmin && iv->t_enter <= tmax) {
        return iv->t_enter;
    }
    if (iv->t_exit >= tmin && iv->t_exit <= tmax) {
        return iv->t_exit;
    }
    return std::nullopt;
}

/// Length (in units of |d|) of the part of the segment [tmin, tmax] inside the sphere: the
/// "thickness" an orthographic view integrates into the volume (exit - entry for a ray that
/// passes right through).
[[nodiscard]] inline double sphere_chord(const Vec3d& o, const Vec3d& d, const Sphere& s,
                                         double tmin, double tmax) {
    const auto iv = intersect_sphere_line(o, d, s);
    if (!iv) {
        return 0.0;
    }
    const double lo = std::fmax(iv->t_enter, tmin);
    const double hi = std::fmin(iv->t_exit, tmax);
    return hi > lo ? hi - lo : 0.0;
}

}  // namespace beamtrace
