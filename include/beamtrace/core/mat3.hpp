// Row-major 3x3 matrix value type.
#pragma once

#include <array>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct Mat3 {
    std::array<std::array<double, 3>, 3> m{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

    [[nodiscard]] static constexpr Mat3 identity() { return Mat3{}; }
    [[nodiscard]] constexpr double operator()(int r, int c) const { return m[r][c]; }
    [[nodiscard]] constexpr double& operator()(int r, int c) { return m[r][c]; }

    [[nodiscard]] constexpr Mat3 transposed() const {
        Mat3 t;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) {
                t.m[r][c] = m[c][r];
            }
        }
        return t;
    }
};

[[nodiscard]] constexpr Mat3 operator*(const Mat3& a, const Mat3& b) {
    Mat3 r;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
        }
    }
    return r;
}

/// Column-vector product M * v.
[[nodiscard]] constexpr Vec3d operator*(const Mat3& a, const Vec3d& v) {
    return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
            a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
            a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}

/// Row-vector product v * M (the Matlab convention `D*R` of the ladar simulator report).
[[nodiscard]] constexpr Vec3d mul_row(const Vec3d& v, const Mat3& a) {
    return {v.x * a.m[0][0] + v.y * a.m[1][0] + v.z * a.m[2][0],
            v.x * a.m[0][1] + v.y * a.m[1][1] + v.z * a.m[2][1],
            v.x * a.m[0][2] + v.y * a.m[1][2] + v.z * a.m[2][2]};
}

}  // namespace beamtrace
