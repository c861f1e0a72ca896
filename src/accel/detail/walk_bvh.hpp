// The front-to-back walk of a BVH, and a ray taken into an instance's object coordinates: what
// the own backends and the moving instances share.
#pragma once

#include <cstdint>

#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/core/affine.hpp"
#include "trace_ray.hpp"

namespace beamtrace::detail {

/// Front-to-back walk of a BVH: on_prim(prim id) for the prims of every leaf the ray reaches
/// before `vis.limit()`; stops (and returns true) when on_prim returns true.
template <class Visitor, class OnPrim>
bool walk_bvh(const Bvh& bvh, const TraceRay& r, const Visitor& vis, const OnPrim& on_prim) {
    if (bvh.nodes.empty()) {
        return false;
    }
    struct Entry {
        std::uint32_t node;
        float tnear;
    };
    Entry stack[128];
    int sp = 0;
    const BvhNode* nodes = bvh.nodes.data();
    float tnear = 0.0f;
    if (!slab_entry(r, nodes[0].lo, nodes[0].hi, r.tmin, vis.limit(), tnear)) {
        return false;
    }
    std::uint32_t index = 0;
    for (;;) {
        const BvhNode& node = nodes[index];
        if (node.is_leaf()) {
            for (std::uint32_t k = node.index; k < node.index + node.count; ++k) {
                if (on_prim(bvh.prim_ids[k])) {
                    return true;
                }
            }
        } else {
            const std::uint32_t li = node.index, ri = node.index + 1;
            const float limit = vis.limit();
            float tl = 0.0f, tr = 0.0f;
            const bool hl = slab_entry(r, nodes[li].lo, nodes[li].hi, r.tmin, limit, tl);
            const bool hr = slab_entry(r, nodes[ri].lo, nodes[ri].hi, r.tmin, limit, tr);
            if (hl && hr) {
                if (tl <= tr) {
                    stack[sp++] = {ri, tr};
                    index = li;
                } else {
                    stack[sp++] = {li, tl};
                    index = ri;
                }
                continue;
            }
            if (hl || hr) {
                index = hl ? li : ri;
                continue;
            }
        }
        // Pop the next node that may still hold a closer hit.
        for (;;) {
            if (sp == 0) {
                return false;
            }
            const Entry e = stack[--sp];
            if (e.tnear <= vis.limit()) {
                index = e.node;
                break;
            }
        }
    }
}

/// The ray in an instance's object coordinates: the direction is not renormalised, so distances
/// along it are world distances and tmin/tmax/limits carry over unchanged.
[[nodiscard]] inline TraceRay to_object(const TraceRay& r, const Affine3& to_object) {
    TraceRay o;
    o.org = Vec3f(to_object.apply_point(Vec3d(r.org)));
    o.dir = Vec3f(to_object.apply_vector(Vec3d(r.dir)));
    o.inv_dir = slab_inverse(o.dir);
    o.tmin = r.tmin;
    o.tmax = r.tmax;
    o.wt = make_watertight_ray(o.org, o.dir);
    return o;
}

}  // namespace beamtrace::detail
