// Affine map p -> linear * p + translation (double precision): the placement of a mesh instance.
#pragma once

#include "beamtrace/core/mat3.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct Affine3 {
    Mat3 linear;                 ///< rotation times scale (any invertible matrix)
    Vec3d translation{0, 0, 0};  ///< metres

    [[nodiscard]] Vec3d apply_point(const Vec3d& p) const { return linear * p + translation; }
    [[nodiscard]] Vec3d apply_vector(const Vec3d& v) const { return linear * v; }
    [[nodiscard]] bool is_identity() const {
        return linear.m == Mat3::identity().m && translation.x == 0 && translation.y == 0 &&
               translation.z == 0;
    }
    /// Determinant of the linear part (0 means the map is not invertible).
    [[nodiscard]] double determinant() const;
    /// The inverse map; throws ConfigError when the linear part is singular.
    [[nodiscard]] Affine3 inverse() const;
};

/// a after b: p -> a(b(p)).
[[nodiscard]] inline Affine3 operator*(const Affine3& a, const Affine3& b) {
    return {a.linear * b.linear, a.linear * b.translation + a.translation};
}

}  // namespace beamtrace
