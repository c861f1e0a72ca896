#include "beamtrace/accel/moving_instances.hpp"

#include <algorithm>
#include <cassert>
#include <optional>

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
        placements_.push_back(place(mi, motions[mi.motion], mesh_bounds_[mi.mesh]));
    }
}

namespace {

/// Whether `how` keeps one attitude at all times (no spin; keys all of one attitude).
bool never_turns(const RigidMotion& how) {
    if (how.keys.empty()) {
        return how.spin_rate_rad_s == 0.0;
    }
    const Quat& q = how.keys.front().attitude;
    return std::all_of(how.keys.begin(), how.keys.end(), [&](const MotionKey& k) {
        return k.attitude.w == q.w && k.attitude.x == q.x && k.attitude.y == q.y &&
               k.attitude.z == q.z;
    });
}

}  // namespace

MovingInstances::Placement MovingInstances::place(const MovingInstance& mi, const RigidMotion& how,
                                                  const Aabb& object_box) {
    Placement pl{mi.local.inverse(), mi.local.determinant() < 0.0};
    pl.still_attitude = never_turns(how) && !object_box.empty();
    if (!pl.still_attitude) {
        return pl;
    }
    const Quat q = how.at(0.0).attitude;
    pl.shift_only = q.w == 1.0 && q.x == 0.0 && q.y == 0.0 && q.z == 0.0 &&
                    pl.local_inverse.linear.m == Mat3::identity().m;
    // The mesh's box corners in the motion's frame, turned by its one attitude, and the offset:
    // the swept box over any span is then the path's box plus this one (prepare()).
    double reach = 0.0;
    for (int c = 0; c < 8; ++c) {
        const Vec3d corner((c & 1) ? object_box.hi.x : object_box.lo.x,
                           (c & 2) ? object_box.hi.y : object_box.lo.y,
                           (c & 4) ? object_box.hi.z : object_box.lo.z);
        const Vec3d m = mi.local.apply_point(corner);
        reach = std::max(reach, length(m));
        const Vec3d w = q.rotate(m) + mi.offset_m;
        pl.box_lo = c == 0 ? w : min(pl.box_lo, w);
        pl.box_hi = c == 0 ? w : max(pl.box_hi, w);
    }
    pl.pad_m = 1e-6 * (reach + length(mi.offset_m)) + 1e-6;
    return pl;
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

Aabb MovingInstances::swept_box(std::size_t k, double t0, double t1) const {
    const MovingInstance& mi = instances_[k];
    const RigidMotion& how = motions_[mi.motion];
    const Placement& pl = placements_[k];
    if (!pl.still_attitude) {
        return mi.swept_bounds(mesh_bounds_[mi.mesh], how, t0, t1);
    }
    // The path's box: its ends and the keys between them (positions are linear between keys).
    const bool keyed = !how.keys.empty();
    Vec3d lo = keyed ? how.at(t0).position_m : how.pivot_m + how.velocity_mps * t0;
    const Vec3d end = keyed ? how.at(t1).position_m : how.pivot_m + how.velocity_mps * t1;
    Vec3d hi = max(lo, end);
    lo = min(lo, end);
    if (keyed) {
        const auto first =
            std::upper_bound(how.keys.begin(), how.keys.end(), t0,
                             [](double t, const MotionKey& key) { return t < key.time_s; });
        for (auto key = first; key != how.keys.end() && key->time_s < t1; ++key) {
            lo = min(lo, key->position_m);
            hi = max(hi, key->position_m);
        }
    }
    // A margin for the float rounding of the traced rays, as in MovingInstance::swept_bounds. It
    // is at least 1e-6 of each coordinate's size (|path.lo| + |box_lo| <= |path.lo| + reach +
    // |offset|), far above the half float ulp (6e-8 of it) of the conversion below: rounding
    // to the nearest float keeps the box around the part.
    const double pad = pl.pad_m + 1e-6 * (length(hi - lo) + length(lo));
    lo = lo + pl.box_lo - Vec3d{pad, pad, pad};
    hi = hi + pl.box_hi + Vec3d{pad, pad, pad};
    return Aabb{Vec3f(lo), Vec3f(hi)};
}

void MovingInstances::prepare(double t0, double t1, MovingFrame& frame, ThreadPool& pool) const {
    frame.t0 = t0;
    frame.t1 = t1;
    frame.boxes.resize(instances_.size());
    for (std::size_t k = 0; k < instances_.size(); ++k) {
        frame.boxes[k] = swept_box(k, t0, t1);
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

Vec3d MovingInstances::position_at(std::size_t k, double time) const {
    const RigidMotion& how = motions_[instances_[k].motion];
    return how.keys.empty() ? how.pivot_m + how.velocity_mps * time : how.at(time).position_m;
}

bool MovingInstances::to_object(std::size_t k, const detail::TraceRay& world, const Vec3d& org,
                                const Vec3d& dir, double time, detail::TraceRay& local) const {
    const MovingInstance& mi = instances_[k];
    const Placement& pl = placements_[k];
    if (pl.shift_only) {  // only the origin moves: the direction stays the world's
        const Vec3d o = org - position_at(k, time) - mi.offset_m + pl.local_inverse.translation;
        local.org = Vec3f(o);
        local.dir = world.dir;
        local.inv_dir = world.inv_dir;
        return true;
    }
    // World -> object: the inverse pose at the ray's time, then the inverse local map.
    const Pose pose = motions_[mi.motion].at(time);
    Vec3d o = org - pose.position_m - mi.offset_m, d = dir;
    if (pose.attitude.w != 1.0) {  // a turned part (w = 1 exactly: no rotation)
        const Quat back = pose.attitude.conjugate();
        o = back.rotate(o);
        d = back.rotate(d);
    }
    local.org = Vec3f(pl.local_inverse.apply_point(o));
    local.dir = Vec3f(pl.local_inverse.apply_vector(d));
    local.inv_dir = Vec3f(1.0f / local.dir.x, 1.0f / local.dir.y, 1.0f / local.dir.z);
    return false;
}

namespace {

/// The watertight set-up of `local` (ray `world` in an instance's object coordinates), made when
/// the instance's mesh first reaches a leaf: that of the world direction, made once per ray, when
/// the instance only shifts.
struct LazySetUp {
    const detail::TraceRay& world;
    std::optional<WatertightRay> world_wt;

    void make(detail::TraceRay& local, bool shifted) {
        if (!shifted) {
            local.wt = make_watertight_ray(local.org, local.dir);
            return;
        }
        if (!world_wt) {
            world_wt = make_watertight_ray(world.org, world.dir);
        }
        local.wt = *world_wt;
        local.wt.org = local.org;
    }
};

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
        TraceRay local = r;
        LazySetUp set_up{r, std::nullopt};
        detail::walk_bvh(frame.top, r, vis, [&](std::uint32_t k) {
            const Aabb& b = frame.boxes[k];  // a leaf's box may hold two instances
            const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
            float entry = 0.0f;
            if (!detail::slab_entry(r, lo, hi, r.tmin, vis.limit(), entry)) {
                return false;
            }
            const MovingInstance& mi = instances_[k];
            const bool shifted = to_object(k, r, org, dir, time, local);
            vis.enter((*meshes_)[mi.mesh], local, mi.first_face, placements_[k].mirrored);
            bool ready = false;  // the set-up only once a leaf of the mesh is reached
            return detail::walk_bvh(blas_[mi.mesh], local, vis, [&](std::uint32_t face) {
                if (!ready) {
                    set_up.make(local, shifted);
                    ready = true;
                }
                return vis.visit(face);
            });
        });
        vis.store(hits, i);
    }
}

}  // namespace beamtrace
