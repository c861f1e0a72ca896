// Rigid motion of scene parts over time (docs/scene-file.md, `motion:`): keyframes (position
// linear, attitude slerp, held outside the key range) or a constant velocity and spin about a
// pivot. A moving instance is a mesh placed by such a motion at each time; the survey traces it
// at each pulse's own time (accel/moving_instances.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include "beamtrace/core/aabb.hpp"
#include "beamtrace/core/affine.hpp"
#include "beamtrace/core/quat.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct MotionKey {
    double time_s = 0.0;
    Vec3d position_m{0, 0, 0};
    Quat attitude;
};

/// A pose over time. With keys: the pose of the keys, interpolated (position linearly, attitude
/// by slerp) and held before the first and after the last. Without: position
/// pivot_m + velocity_mps t and attitude the spin about spin_axis by spin_rate_rad_s t.
struct RigidMotion {
    std::vector<MotionKey> keys;  ///< sorted by time (strictly increasing); empty: constant
    Vec3d pivot_m{0, 0, 0};       ///< constant motion: position at time 0
    Vec3d velocity_mps{0, 0, 0};
    Vec3d spin_axis{0, 0, 1};  ///< unit
    double spin_rate_rad_s = 0.0;

    /// The pose at time t (seconds on the survey's clock).
    [[nodiscard]] Pose at(double t) const;
    /// The velocity (m/s) at time t of the body point that is at `p` (scene coordinates).
    [[nodiscard]] Vec3d point_velocity(const Vec3d& p, double t) const;
    /// The box of the positions over [t0, t1].
    [[nodiscard]] Aabb position_bounds(double t0, double t1) const;
    /// True when the attitude changes somewhere in [t0, t1].
    [[nodiscard]] bool rotates_in(double t0, double t1) const;
};

/// A mesh placed by a motion: at time t its object coordinates map to the scene by
/// offset_m + pose(t) * local.
struct MovingInstance {
    std::uint32_t mesh = 0;        ///< index into SceneGeometry::meshes
    std::uint32_t first_face = 0;  ///< global face ID of the mesh's face 0
    std::uint32_t motion = 0;      ///< index into the scene's motions
    Affine3 local;                 ///< object coordinates -> the motion's frame
    Vec3d offset_m{0, 0, 0};       ///< added after the motion (an array copy's step)

    /// Object -> scene coordinates with the motion at `pose`.
    [[nodiscard]] Affine3 to_world(const Pose& pose) const;
    /// Bounds of the mesh (its object-space box `object_box`) over [t0, t1] under `motion`.
    [[nodiscard]] Aabb swept_bounds(const Aabb& object_box, const RigidMotion& how, double t0,
                                    double t1) const;
};

}  // namespace beamtrace
