#include "beamtrace/accel/moving_instances.hpp"

#include <cassert>

#include "detail/queries.hpp"
#include "detail/walk_bvh.hpp"

namespace beamtrace {

MovingInstances::MovingInstances(const std::vector<TriangleMesh>& meshes,
                                 std::span<const MovingInstance> instances,
                                 std::span<const RigidMotion> motions,
                                 const BvhBuildConfig& config, ThreadPool& pool)
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

void MovingInstances::prepare(double t0, double t1, MovingFrame& frame, ThreadPool& pool) const {
    frame.t0 = t0;
    frame.t1 = t1;
    frame.boxes.resize(instances_.size());
    for (std::size_t k = 0; k < instances_.size(); ++k) {
        const MovingInstance& mi = instances_[k];
        frame.boxes[k] = mi.swept_bounds(mesh_bounds_[mi.mesh], motions_[mi.motion], t0, t1);
    }
    frame.top = build_bvh(std::span<const Aabb>(frame.boxes), top_config_, pool);
}

void MovingInstances::intersect(const RayBatch& rays, std::size_t begin, std::size_t end,
                                std::span<const double> ray_time_s, const MovingFrame& frame,
                                HitBatch& hits) const {
    using detail::TraceRay;
    for (std::size_t i = begin; i < end; ++i) {
        const double time = ray_time_s[i - begin];
        assert(time >= frame.t0 && time <= frame.t1);
        const TraceRay r = detail::make_trace_ray(rays, i);
        detail::NearestVisitor vis(r);
        vis.start_from(hits, i);
        const Vec3d org = rays.origin(i), dir = rays.direction(i);
        detail::walk_bvh(frame.top, r, vis, [&](std::uint32_t k) {
            const MovingInstance& mi = instances_[k];
            const Placement& pl = placements_[k];
            // World -> object: the inverse pose at the ray's time, then the inverse local map.
            const Pose pose = motions_[mi.motion].at(time);
            const Quat back = pose.attitude.conjugate();
            const Vec3d o = pl.local_inverse.apply_point(
                back.rotate(org - pose.position_m - mi.offset_m));
            const Vec3d d = pl.local_inverse.apply_vector(back.rotate(dir));
            TraceRay local = r;
            local.org = Vec3f(o);
            local.dir = Vec3f(d);
            local.inv_dir = Vec3f(1.0f / local.dir.x, 1.0f / local.dir.y, 1.0f / local.dir.z);
            local.wt = make_watertight_ray(local.org, local.dir);
            vis.enter((*meshes_)[mi.mesh], local, mi.first_face, pl.mirrored);
            return detail::walk_bvh(blas_[mi.mesh], local, vis,
                                    [&](std::uint32_t face) { return vis.visit(face); });
        });
        vis.store(hits, i);
    }
}

}  // namespace beamtrace
