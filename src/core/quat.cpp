#include "beamtrace/core/quat.hpp"

#include <cmath>

namespace beamtrace {

Quat Quat::from_matrix(const Mat3& m) {
    // Shepperd's method: pick the largest of w, x, y, z for stability.
    const double tr = m(0, 0) + m(1, 1) + m(2, 2);
    Quat q;
    if (tr > 0.0) {
        const double s = std::sqrt(tr + 1.0) * 2.0;
        q = {0.25 * s, (m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s};
    } else if (m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2)) {
        const double s = std::sqrt(1.0 + m(0, 0) - m(1, 1) - m(2, 2)) * 2.0;
        q = {(m(2, 1) - m(1, 2)) / s, 0.25 * s, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s};
    } else if (m(1, 1) > m(2, 2)) {
        const double s = std::sqrt(1.0 + m(1, 1) - m(0, 0) - m(2, 2)) * 2.0;
        q = {(m(0, 2) - m(2, 0)) / s, (m(0, 1) + m(1, 0)) / s, 0.25 * s, (m(1, 2) + m(2, 1)) / s};
    } else {
        const double s = std::sqrt(1.0 + m(2, 2) - m(0, 0) - m(1, 1)) * 2.0;
        q = {(m(1, 0) - m(0, 1)) / s, (m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, 0.25 * s};
    }
    return q.normalized();
}

Quat Quat::from_rpy(const RollPitchYaw& rpy) {
    // d * R (row vector) == R^T d (column vector).
    return from_matrix(rpy_matrix(rpy).transposed());
}

Quat Quat::from_axis_angle(const Vec3d& axis, double angle_rad) {
    const Vec3d a = normalize(axis);
    const double s = std::sin(0.5 * angle_rad);
    return {std::cos(0.5 * angle_rad), a.x * s, a.y * s, a.z * s};
}

Mat3 Quat::to_matrix() const {
    Mat3 m;
    m.m = {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
            {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
            {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
    return m;
}

Quat Quat::normalized() const {
    const double n = std::sqrt(w * w + x * x + y * y + z * z);
    return {w / n, x / n, y / n, z / n};
}

Quat operator*(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Quat slerp(const Quat& a, const Quat& b_in, double t) {
    Quat b = b_in;
    double c = dot(a, b);
    if (c < 0.0) {  // shorter arc
        b = {-b.w, -b.x, -b.y, -b.z};
        c = -c;
    }
    if (c > 0.9995) {  // nearly equal: normalised lerp
        return Quat{a.w + t * (b.w - a.w), a.x + t * (b.x - a.x), a.y + t * (b.y - a.y),
                    a.z + t * (b.z - a.z)}
            .normalized();
    }
    const double theta = std::acos(c);
    const double s = std::sin(theta);
    const double wa = std::sin((1.0 - t) * theta) / s, wb = std::sin(t * theta) / s;
    return {wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z};
}

}  // namespace beamtrace
