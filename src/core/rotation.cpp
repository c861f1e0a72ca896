#include "beamtrace/core/rotation.hpp"

#include <cmath>

namespace beamtrace {

Mat3 rpy_matrix(const RollPitchYaw& rpy) {
    const double cr = std::cos(rpy.roll_rad), sr = std::sin(rpy.roll_rad);
    const double cp = std::cos(rpy.pitch_rad), sp = std::sin(rpy.pitch_rad);
    const double cy = std::cos(rpy.yaw_rad), sy = std::sin(rpy.yaw_rad);
    Mat3 rx, ry, rz;
    rx.m = {{{1, 0, 0}, {0, cr, -sr}, {0, sr, cr}}};
    ry.m = {{{cp, 0, sp}, {0, 1, 0}, {-sp, 0, cp}}};
    rz.m = {{{cy, -sy, 0}, {sy, cy, 0}, {0, 0, 1}}};
    return rx * ry * rz;
}

}  // namespace beamtrace
