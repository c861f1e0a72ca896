// Roll-pitch-yaw rotations with the conventions of the ladar simulator report (Appendix A).
#pragma once

#include "beamtrace/core/mat3.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// Roll, pitch and yaw in radians. Sensor frame: x forward (optical axis), y left, z up.
struct RollPitchYaw {
    double roll_rad = 0.0;
    double pitch_rad = 0.0;
    double yaw_rad = 0.0;
};

/// The report's `R = Rx(roll) * Ry(pitch) * Rz(yaw)`; a sensor-frame row vector `d` maps to the
/// world as `d * R` (see `sensor_to_world`).
[[nodiscard]] Mat3 rpy_matrix(const RollPitchYaw& rpy);

/// Rotates a sensor-frame direction into the world frame exactly like the report's `D*R`.
[[nodiscard]] inline Vec3d sensor_to_world(const Vec3d& d, const Mat3& r) {
    return mul_row(d, r);
}

}  // namespace beamtrace
