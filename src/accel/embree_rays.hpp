// Our rays in Embree's ray structures (double precision in, single out), shared by the Embree
// backend and the raw-Embree limit so both trace exactly the same rays.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstddef>

#include "beamtrace/core/ray_batch.hpp"

namespace beamtrace::detail {

/// Ray i of `rays` as one Embree ray (mask all, time 0).
inline void set_embree_ray(RTCRay& r, const RayBatch& rays, std::size_t i) {
    r.org_x = static_cast<float>(rays.ox[i]);
    r.org_y = static_cast<float>(rays.oy[i]);
    r.org_z = static_cast<float>(rays.oz[i]);
    r.dir_x = static_cast<float>(rays.dx[i]);
    r.dir_y = static_cast<float>(rays.dy[i]);
    r.dir_z = static_cast<float>(rays.dz[i]);
    r.tnear = static_cast<float>(rays.tmin[i]);
    r.tfar = static_cast<float>(rays.tmax[i]);
    r.time = 0.0f;
    r.mask = 0xFFFFFFFFu;
    r.id = 0;
    r.flags = 0;
}

/// Sets the lanes' fields that tracing never changes (time, mask, id, flags): once per packet
/// structure, before set_embree_packet fills it again and again.
inline void init_embree_packet(RTCRayHit16& rh) {
    for (std::size_t k = 0; k < 16; ++k) {
        rh.ray.time[k] = 0.0f;
        rh.ray.mask[k] = 0xFFFFFFFFu;
        rh.ray.id[k] = 0;
        rh.ray.flags[k] = 0;
    }
}

/// Rays [first, first + n) (1 <= n <= 16) into a packet set up by init_embree_packet, with no
/// hit yet; idle lanes repeat the last ray and are marked invalid.
inline void set_embree_packet(RTCRayHit16& rh, int valid[16], const RayBatch& rays,
                              std::size_t first, std::size_t n) {
    for (std::size_t k = 0; k < 16; ++k) {
        const std::size_t i = first + std::min(k, n - 1);
        valid[k] = k < n ? -1 : 0;
        rh.ray.org_x[k] = static_cast<float>(rays.ox[i]);
        rh.ray.org_y[k] = static_cast<float>(rays.oy[i]);
        rh.ray.org_z[k] = static_cast<float>(rays.oz[i]);
        rh.ray.dir_x[k] = static_cast<float>(rays.dx[i]);
        rh.ray.dir_y[k] = static_cast<float>(rays.dy[i]);
        rh.ray.dir_z[k] = static_cast<float>(rays.dz[i]);
        rh.ray.tnear[k] = static_cast<float>(rays.tmin[i]);
        rh.ray.tfar[k] = static_cast<float>(rays.tmax[i]);
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
}

}  // namespace beamtrace::detail
