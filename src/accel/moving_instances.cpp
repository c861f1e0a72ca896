#include "beamtrace/accel/moving_instances.hpp"

#include <algorithm>
#include <cassert>

#include "detail/queries.hpp"
#include "detail/walk_bvh.hpp"

namespace beamtrace {

MovingInstances::MovingInstances(const std::vector<TriangleMesh>& meshes,
                                 std::span<const MovingInstance> instances,
                                 std::span<const RigidMotion> motions, const BvhBuildConfig& config,
                                 ThreadPool& pool)
    : meshes_(&meshes), instances_(instances), motions_(motions), top_config_(config) {
    top_config_.min_leaf_size = 1;
    top_config_.max_leaf_size = 2;
    blas_.resize(meshes.size());
    mesh_bounds_.resize(meshes.size());
    placements_.reserve(instances.size());
    for (const MovingInstance& mi : instances) {
        if (blas_[mi.mesh].nodes.empty() && !meshes[mi.mesh].faces.empty()) {
            blas_[mi.mesh] = build_bvh(meshes[mi.mesh], config, pool);
            mesh_bounds_[mi.mesh] = meshes[mi.mesh].bounds();
        }
        placements_.push_back({mi.local.inverse(), mi.local.determinant() < 0.0});
    }
}

namespace {

/// Refits `bvh`'s node boxes to `boxes` (children follow their parents, so a reverse sweep sees
/// them first); returns the summed half areas of the nodes.
double refit(Bvh& bvh, std::span<const Aabb> boxes) {
    double cost = 0.0;
    for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
        BvhNode& n = bvh.nodes[i];
        Aabb box;
        if (n.is_leaf()) {
            for (std::uint32_t k = n.index; k < n.index + n.count; ++k) {
                box.extend(boxes[bvh.prim_ids[k]]);
            }
        } else {
            for (const std::uint32_t c : {n.index, n.index + 1}) {  // siblings side by side
                box.extend(Aabb{{bvh.nodes[c].lo[0], bvh.nodes[c].lo[1], bvh.nodes[c].lo[2]},
                                {bvh.nodes[c].hi[0], bvh.nodes[c].hi[1], bvh.nodes[c].hi[2]}});
            }
        }
        for (std::size_t a = 0; a < 3; ++a) {
            n.lo[a] = box.lo[a];
            n.hi[a] = box.hi[a];
        }
        cost += box.half_area();
    }
    return cost;
}

}  // namespace

void MovingInstances::prepare(double t0, double t1, MovingFrame& frame, ThreadPool& pool) const {
    frame.t0 = t0;
    frame.t1 = t1;
    frame.boxes.resize(instances_.size());
    for (std::size_t k = 0; k < instances_.size(); ++k) {
        const MovingInstance& mi = instances_[k];
        frame.boxes[k] = mi.swept_bounds(mesh_bounds_[mi.mesh], motions_[mi.motion], t0, t1);
    }
    if (!frame.top.nodes.empty() && refit(frame.top, frame.boxes) <= 2.0 * frame.built_cost) {
        return;
    }
    frame.top = build_bvh(std::span<const Aabb>(frame.boxes), top_config_, pool);
    frame.built_cost = refit(frame.top, frame.boxes);
}

namespace {

/// Whether box ray `r` (ray i) enters the root box before its hit in `hits`.
bool reaches_root(const detail::TraceRay& r, std::size_t i, const Bvh& top, const HitBatch& hits) {
    if (top.nodes.empty()) {
        return false;
    }
    const float tmax = std::min(r.tmax, hits.face[i] != kNoFace ? hits.t[i] * 1.0001f : hits.t[i]);
    float entry = 0.0f;
    return detail::slab_entry(r, top.nodes[0].lo, top.nodes[0].hi, r.tmin, tmax, entry);
}

}  // namespace

void MovingInstances::intersect(const RayBatch& rays, std::size_t begin, std::size_t end,
                                std::span<const double> ray_time_s, const MovingFrame& frame,
                                HitBatch& hits) const {
    using detail::TraceRay;
    for (std::size_t i = begin; i < end; ++i) {
        const double time = ray_time_s[i - begin];
        assert(time >= frame.t0 && time <= frame.t1);
        const TraceRay r = detail::make_box_ray(rays, i);
        if (!reaches_root(r, i, frame.top, hits)) {
            continue;
        }
        detail::NearestVisitor vis(r);
        vis.start_from(hits, i);
        const Vec3d org = rays.origin(i), dir = rays.direction(i);
        detail::walk_bvh(frame.top, r, vis, [&](std::uint32_t k) {
            const Aabb& b = frame.boxes[k];  // a leaf's box may hold two instances
            const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
            float entry = 0.0f;
            if (!detail::slab_entry(r, lo, hi, r.tmin, vis.limit(), entry)) {
                return false;
            }
            const MovingInstance& mi = instances_[k];
            const Placement& pl = placements_[k];
            // World -> object: the inverse pose at the ray's time, then the inverse local map.
            const Pose pose = motions_[mi.motion].at(time);
            Vec3d o = org - pose.position_m - mi.offset_m, d = dir;
            if (pose.attitude.w != 1.0) {  // a turned part (w = 1 exactly: no rotation)
                const Quat back = pose.attitude.conjugate();
                o = back.rotate(o);
                d = back.rotate(d);
            }
            TraceRay local = r;
            local.org = Vec3f(pl.local_inverse.apply_point(o));
            local.dir = Vec3f(pl.local_inverse.apply_vector(d));
            local.inv_dir = Vec3f(1.0f / local.dir.x, 1.0f / local.dir.y, 1.0f / local.dir.z);
            vis.enter((*meshes_)[mi.mesh], local, mi.first_face, pl.mirrored);
            // The watertight set-up only once a leaf of the mesh is reached.
            bool ready = false;
            return detail::walk_bvh(blas_[mi.mesh], local, vis, [&](std::uint32_t face) {
                if (!ready) {
                    local.wt = make_watertight_ray(local.org, local.dir);
                    ready = true;
                }
                return vis.visit(face);
            });
        });
        vis.store(hits, i);
    }
}

}  // namespace beamtrace
