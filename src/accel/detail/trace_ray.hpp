// Per-ray constants for traversal (float), built once per ray from a double RayBatch slot.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>

#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/geometry/ray_triangle.hpp"

namespace beamtrace::detail {

struct TraceRay {
    Vec3f org, dir, inv_dir;
    float tmin = 0, tmax = std::numeric_limits<float>::infinity();
    WatertightRay wt;
};

/// 1 / d for the slab tests, with -0 taken as +0 (d + 0 is +0 for either zero): an inverse of
/// +inf gives NaN only where the origin lies on a slab's plane and in the operand order that
/// slab_interval ignores (lo - o = 0: the entry; hi - o = 0: the exit), where -inf gave NaN on
/// the other side and a ray along a box's face missed the box (and leaked through its faces).
[[nodiscard]] inline Vec3f slab_inverse(const Vec3f& d) {
    return Vec3f(1.0f / (d.x + 0.0f), 1.0f / (d.y + 0.0f), 1.0f / (d.z + 0.0f));
}

/// Ray i of `rays` for box tests only (no watertight set-up: its triangles are met with a ray
/// of their own, e.g. in an instance's frame).
[[nodiscard]] inline TraceRay make_box_ray(const RayBatch& rays, std::size_t i) {
    TraceRay r;
    r.org = Vec3f(static_cast<float>(rays.ox[i]), static_cast<float>(rays.oy[i]),
                  static_cast<float>(rays.oz[i]));
    r.dir = Vec3f(static_cast<float>(rays.dx[i]), static_cast<float>(rays.dy[i]),
                  static_cast<float>(rays.dz[i]));
    // 1/0 = inf; the slab test below treats the NaN of 0*inf as "inside that slab".
    r.inv_dir = slab_inverse(r.dir);
    r.tmin = static_cast<float>(rays.tmin[i]);
    r.tmax = static_cast<float>(rays.tmax[i]);
    return r;
}

/// Ray i of `rays` with the watertight triangle test's set-up.
[[nodiscard]] inline TraceRay make_trace_ray(const RayBatch& rays, std::size_t i) {
    TraceRay r = make_box_ray(rays, i);
    r.wt = make_watertight_ray(r.org, r.dir);
    return r;
}

/// The interval [entry, exit] of the ray inside the box, within [tmin, tmax], padded outward
/// (Ize 2013: 2*gamma(3)) so that it never loses a hit. NaN from rays parallel to a slab whose
/// origin lies exactly on its plane is ignored by the operand order. False when the box is missed.
[[nodiscard]] inline bool slab_interval(const TraceRay& r, const float lo[3], const float hi[3],
                                        float tmin, float tmax, float& entry, float& exit) {
    constexpr float kPad = 2.0f * 3.0f * std::numeric_limits<float>::epsilon();
    float tnear = tmin, tfar = tmax;
    for (int a = 0; a < 3; ++a) {
        const float o = r.org[static_cast<std::size_t>(a)];
        const float inv = r.inv_dir[static_cast<std::size_t>(a)];
        const float t0 = (lo[a] - o) * inv;
        const float t1 = (hi[a] - o) * inv;
        const float n = (t1 < t0) ? t1 : t0;  // NaN t0 -> t0 -> ignored below
        const float f = (t0 > t1) ? t0 : t1;  // NaN t1 -> t1 -> ignored below
        tnear = (n > tnear) ? n : tnear;
        // Scaled, not offset: f + |f| * pad would be NaN for f = -inf (a box behind the origin
        // on an axis the ray does not move along), and the box would never be culled.
        const float fp = f >= 0.0f ? f * (1.0f + kPad) : f * (1.0f - kPad);
        tfar = (fp < tfar) ? fp : tfar;
    }
    // The entry distance is lowered by the same margin, so culling a node by it is conservative.
    entry = tnear - std::fabs(tnear) * kPad;
    exit = tfar;
    return tnear <= tfar;
}

/// The entry distance only (see slab_interval).
[[nodiscard]] inline bool slab_entry(const TraceRay& r, const float lo[3], const float hi[3],
                                     float tmin, float tmax, float& entry) {
    float exit = 0.0f;
    return slab_interval(r, lo, hi, tmin, tmax, entry, exit);
}

}  // namespace beamtrace::detail
