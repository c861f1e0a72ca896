#include "beamtrace/geometry/rigid_motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace beamtrace {
namespace {

/// The key segment [i, i + 1] holding t (keys.size() >= 2, keys[0].time_s < t < last time).
std::size_t segment_of(const std::vector<MotionKey>& keys, double t) {
    const auto it = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](double v, const MotionKey& k) { return v < k.time_s; });
    return static_cast<std::size_t>(it - keys.begin()) - 1;
}

/// Angular velocity (rad/s, world axes) of the slerp from a to b over dt seconds.
Vec3d angular_velocity(const Quat& a, const Quat& b, double dt) {
    Quat r = b * a.conjugate();
    if (r.w < 0.0) {  // the shorter arc, as slerp takes
        r = {-r.w, -r.x, -r.y, -r.z};
    }
    const double s = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z);
    if (s == 0.0) {
        return {0, 0, 0};
    }
    const double angle = 2.0 * std::atan2(s, r.w);
    return Vec3d{r.x, r.y, r.z} * (angle / (s * dt));
}

void add_point(Aabb& box, const Vec3d& p) {
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (std::size_t a = 0; a < 3; ++a) {
        const auto f = static_cast<float>(p[a]);
        box.lo[a] = std::min(box.lo[a], std::nextafter(f, -kInf));
        box.hi[a] = std::max(box.hi[a], std::nextafter(f, kInf));
    }
}

}  // namespace

Pose RigidMotion::at(double t) const {
    if (keys.empty()) {
        return {pivot_m + velocity_mps * t,
                spin_rate_rad_s == 0.0 ? Quat{}
                                       : Quat::from_axis_angle(spin_axis, spin_rate_rad_s * t)};
    }
    if (t <= keys.front().time_s) {
        return {keys.front().position_m, keys.front().attitude};
    }
    if (t >= keys.back().time_s) {
        return {keys.back().position_m, keys.back().attitude};
    }
    const std::size_t i = segment_of(keys, t);
    const MotionKey& a = keys[i];
    const MotionKey& b = keys[i + 1];
    const double s = (t - a.time_s) / (b.time_s - a.time_s);
    return {a.position_m + (b.position_m - a.position_m) * s, slerp(a.attitude, b.attitude, s)};
}

Vec3d RigidMotion::point_velocity(const Vec3d& p, double t) const {
    const Pose pose = at(t);
    if (keys.empty()) {
        return velocity_mps + cross(spin_axis * spin_rate_rad_s, p - pose.position_m);
    }
    if (t <= keys.front().time_s || t >= keys.back().time_s) {
        return {0, 0, 0};
    }
    const std::size_t i = segment_of(keys, t);
    const MotionKey& a = keys[i];
    const MotionKey& b = keys[i + 1];
    const double dt = b.time_s - a.time_s;
    return (b.position_m - a.position_m) * (1.0 / dt) +
           cross(angular_velocity(a.attitude, b.attitude, dt), p - pose.position_m);
}

Aabb RigidMotion::position_bounds(double t0, double t1) const {
    Aabb box;
    add_point(box, at(t0).position_m);
    add_point(box, at(t1).position_m);
    for (const MotionKey& k : keys) {
        if (k.time_s > t0 && k.time_s < t1) {
            add_point(box, k.position_m);
        }
    }
    return box;
}

bool RigidMotion::rotates_in(double t0, double t1) const {
    if (keys.empty()) {
        return spin_rate_rad_s != 0.0 && t1 > t0;
    }
    const Quat q = at(t0).attitude;
    const auto same = [&](const Quat& r) {
        return r.w == q.w && r.x == q.x && r.y == q.y && r.z == q.z;
    };
    if (!same(at(t1).attitude)) {
        return true;
    }
    return std::any_of(keys.begin(), keys.end(), [&](const MotionKey& k) {
        return k.time_s > t0 && k.time_s < t1 && !same(k.attitude);
    });
}

Affine3 MovingInstance::to_world(const Pose& pose) const {
    const Mat3 r = pose.attitude.to_matrix();
    return {r * local.linear, r * local.translation + pose.position_m + offset_m};
}

Aabb MovingInstance::swept_bounds(const Aabb& object_box, const RigidMotion& how, double t0,
                                  double t1) const {
    if (object_box.empty()) {
        return object_box;
    }
    // The mesh's box corners in the motion's frame, turned by the attitude at t0 when it stays.
    const bool turns = how.rotates_in(t0, t1);
    const Quat q = how.at(t0).attitude;
    Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity()};
    Vec3d hi = lo * -1.0;
    double reach = 0.0;  // farthest corner from the motion's origin
    for (int c = 0; c < 8; ++c) {
        const Vec3d corner((c & 1) ? object_box.hi.x : object_box.lo.x,
                           (c & 2) ? object_box.hi.y : object_box.lo.y,
                           (c & 4) ? object_box.hi.z : object_box.lo.z);
        const Vec3d m = local.apply_point(corner);
        reach = std::max(reach, length(m));
        const Vec3d w = q.rotate(m);
        lo = min(lo, w);
        hi = max(hi, w);
    }
    if (turns) {
        lo = Vec3d{-reach, -reach, -reach};
        hi = Vec3d{reach, reach, reach};
    }
    const Aabb path = how.position_bounds(t0, t1);
    // A margin for the float rounding of the traced rays (1e-6 of the sizes involved).
    const double pad = 1e-6 * (reach + length(Vec3d(path.hi) - Vec3d(path.lo)) + length(offset_m) +
                               length(Vec3d(path.lo))) +
                       1e-6;
    Aabb box;
    add_point(box, Vec3d(path.lo) + lo + offset_m - Vec3d{pad, pad, pad});
    add_point(box, Vec3d(path.hi) + hi + offset_m + Vec3d{pad, pad, pad});
    return box;
}

}  // namespace beamtrace
