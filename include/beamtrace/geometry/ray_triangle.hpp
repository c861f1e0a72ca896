// Exact ray/triangle intersection.
//
// `intersect_watertight` is the watertight test of Woop, Benthin and Wald (JCGT 2013): a ray that
// passes through a shared edge or vertex of a closed mesh hits at least one of the triangles that
// share it, in float, with a double-precision fallback for the exactly-on-edge case. Every backend
// uses it, so backends agree bit for bit on the same triangle.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// Which sides of a triangle count, as in BrainStorm's `ray_intersect` cull modes. The front is the
/// side from which V0 -> V1 -> V2 turns counter-clockwise (the side the normal (V1-V0)x(V2-V0)
/// points to).
enum class Facing : std::uint8_t {
    front,  ///< 'o': the ray enters through the front (outside to inside of a closed surface)
    back,   ///< 'i': the ray leaves through the back (inside to outside)
    both,   ///< 'b'
};

/// Per-ray constants of the watertight test.
struct WatertightRay {
    Vec3f org;
    int kx = 0, ky = 1, kz = 2;
    float sx = 0, sy = 0, sz = 1;
};

[[nodiscard]] inline WatertightRay make_watertight_ray(const Vec3f& org, const Vec3f& dir) {
    WatertightRay r;
    r.org = org;
    const float ax = std::fabs(dir.x), ay = std::fabs(dir.y), az = std::fabs(dir.z);
    r.kz = (ax > ay) ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    if (dir[static_cast<std::size_t>(r.kz)] < 0.0f) {
        std::swap(r.kx, r.ky);
    }
    const float dz = dir[static_cast<std::size_t>(r.kz)];
    r.sx = dir[static_cast<std::size_t>(r.kx)] / dz;
    r.sy = dir[static_cast<std::size_t>(r.ky)] / dz;
    r.sz = 1.0f / dz;
    return r;
}

/// A ray/triangle hit: distance along the ray and barycentrics of V1 (u) and V2 (v), so the point
/// is (1-u-v) V0 + u V1 + v V2.
struct TriangleHit {
    float t = 0;
    float u = 0;
    float v = 0;
    bool front = true;  ///< the ray met the front side
};

/// True when the ray meets triangle (a, b, c) at tmin <= t <= tmax on a side allowed by `facing`.
[[nodiscard]] inline bool intersect_watertight(const WatertightRay& r, const Vec3f& a,
                                               const Vec3f& b, const Vec3f& c, float tmin,
                                               float tmax, Facing facing, TriangleHit& hit) {
    const auto kx = static_cast<std::size_t>(r.kx);
    const auto ky = static_cast<std::size_t>(r.ky);
    const auto kz = static_cast<std::size_t>(r.kz);
    const Vec3f A = a - r.org, B = b - r.org, C = c - r.org;
    const float Ax = A[kx] - r.sx * A[kz], Ay = A[ky] - r.sy * A[kz];
    const float Bx = B[kx] - r.sx * B[kz], By = B[ky] - r.sy * B[kz];
    const float Cx = C[kx] - r.sx * C[kz], Cy = C[ky] - r.sy * C[kz];
    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        // Exactly on an edge in float: decide in double so neighbours agree.
        U = static_cast<float>(double(Cx) * double(By) - double(Cy) * double(Bx));
        V = static_cast<float>(double(Ax) * double(Cy) - double(Ay) * double(Cx));
        W = static_cast<float>(double(Bx) * double(Ay) - double(By) * double(Ax));
    }
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) {
        return false;
    }
    const float det = U + V + W;
    if (det == 0.0f) {
        return false;
    }
    const bool front = det > 0.0f;
    if ((facing == Facing::front && !front) || (facing == Facing::back && front)) {
        return false;
    }
    const float Az = r.sz * A[kz], Bz = r.sz * B[kz], Cz = r.sz * C[kz];
    const float T = U * Az + V * Bz + W * Cz;
    if (front ? (T < tmin * det || T > tmax * det) : (T > tmin * det || T < tmax * det)) {
        return false;
    }
    const float inv = 1.0f / det;
    hit.t = T * inv;
    hit.u = V * inv;
    hit.v = W * inv;
    hit.front = front;
    return hit.t >= tmin && hit.t <= tmax;
}

}  // namespace beamtrace
