#include "beamtrace/core/affine.hpp"

#include <cmath>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

double Affine3::determinant() const {
    const auto& a = linear.m;
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

Affine3 Affine3::inverse() const {
    const double det = determinant();
    if (!std::isfinite(det) || det == 0.0) {
        throw ConfigError("transform is not invertible (determinant " + std::to_string(det) + ")");
    }
    const auto& a = linear.m;
    Affine3 r;
    auto& b = r.linear.m;
    b[0][0] = (a[1][1] * a[2][2] - a[1][2] * a[2][1]) / det;
    b[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
    b[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
    b[1][0] = (a[1][2] * a[2][0] - a[1][0] * a[2][2]) / det;
    b[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
    b[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
    b[2][0] = (a[1][0] * a[2][1] - a[1][1] * a[2][0]) / det;
    b[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
    b[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
    r.translation = -(r.linear * translation);
    return r;
}

}  // namespace beamtrace
