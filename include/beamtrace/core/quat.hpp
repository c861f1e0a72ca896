// Unit quaternions for attitudes, and rigid poses built on them.
#pragma once

#include "beamtrace/core/mat3.hpp"
#include "beamtrace/core/rotation.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// A unit quaternion w + xi + yj + zk acting on column vectors: v' = q v q*.
struct Quat {
    double w = 1.0, x = 0.0, y = 0.0, z = 0.0;

    [[nodiscard]] static Quat identity() { return {}; }
    /// The rotation of a column-vector matrix (must be orthonormal, det +1).
    [[nodiscard]] static Quat from_matrix(const Mat3& m);
    /// The sensor-to-world attitude of the report's [roll pitch yaw]: rotate(d) == d * R with
    /// R = Rx*Ry*Rz, i.e. exactly `sensor_to_world(d, rpy_matrix(rpy))`.
    [[nodiscard]] static Quat from_rpy(const RollPitchYaw& rpy);
    /// Rotation by `angle_rad` about the unit vector `axis` (right-handed).
    [[nodiscard]] static Quat from_axis_angle(const Vec3d& axis, double angle_rad);

    [[nodiscard]] Mat3 to_matrix() const;
    /// v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z). Inline: it runs several times per pulse.
    [[nodiscard]] Vec3d rotate(const Vec3d& v) const {
        const Vec3d u{x, y, z};
        const Vec3d t = cross(u, v) * 2.0;
        return v + t * w + cross(u, t);
    }
    [[nodiscard]] Quat conjugate() const { return {w, -x, -y, -z}; }
    [[nodiscard]] Quat normalized() const;
};

/// Hamilton product: (a * b).rotate(v) == a.rotate(b.rotate(v)).
[[nodiscard]] Quat operator*(const Quat& a, const Quat& b);
[[nodiscard]] inline double dot(const Quat& a, const Quat& b) {
    return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}
/// Spherical linear interpolation along the shorter arc, t in [0, 1].
[[nodiscard]] Quat slerp(const Quat& a, const Quat& b, double t);

/// A rigid transform from a local frame (sensor, platform) to its parent (platform, world):
/// parent = position + attitude.rotate(local).
struct Pose {
    Vec3d position_m;
    Quat attitude;

    [[nodiscard]] Vec3d apply_point(const Vec3d& p) const {
        return position_m + attitude.rotate(p);
    }
    [[nodiscard]] Vec3d apply_direction(const Vec3d& d) const { return attitude.rotate(d); }
};

/// (a * b) maps b's local frame through b then a: (a * b).apply_point(p) ==
/// a.apply_point(b.apply_point(p)).
[[nodiscard]] inline Pose operator*(const Pose& a, const Pose& b) {
    return {a.apply_point(b.position_m), a.attitude * b.attitude};
}

}  // namespace beamtrace
