#include "beamtrace/accel/moving_instances.hpp"

#include <algorithm>
#include <cassert>
#include <limits>
#include <memory>
#include <optional>

#include "detail/queries.hpp"
#include "detail/walk_bvh.hpp"

namespace beamtrace {

MovingInstances::MovingInstances(const std::vector<TriangleMesh>& meshes,
                                 std::span<const MovingInstance> instances,
                                 std::span<const RigidMotion> motions, const BvhBuildConfig& config,
                                 ThreadPool& pool, BackendKind groups)
    : meshes_(&meshes), instances_(instances), motions_(motions), top_config_(config) {
    top_config_.min_leaf_size = 1;
    top_config_.max_leaf_size = 2;
    blas_.resize(meshes.size());
    mesh_bounds_.resize(meshes.size());
    placements_.reserve(instances.size());
    for (const MovingInstance& mi : instances) {
        if (mesh_bounds_[mi.mesh].empty() && !meshes[mi.mesh].faces.empty()) {
            mesh_bounds_[mi.mesh] = meshes[mi.mesh].bounds();
        }
        placements_.push_back(place(mi, motions[mi.motion]));
    }
    make_movers(pool, groups);
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

/// The most faces a flattened run holds (a longer run is split): bounds the copies' memory.
constexpr std::size_t kMaxFlatFaces = std::size_t{1} << 20;
/// The most runs traced as groups (each is a pass over every ray); later runs are movers.
constexpr std::size_t kMaxGroups = 4;

}  // namespace

MovingInstances::Placement MovingInstances::place(const MovingInstance& mi,
                                                  const RigidMotion& how) {
    Placement pl{mi.local.inverse(), mi.local.determinant() < 0.0};
    const Quat q = how.at(0.0).attitude;
    pl.shift_only = never_turns(how) && q.w == 1.0 && q.x == 0.0 && q.y == 0.0 && q.z == 0.0 &&
                    pl.local_inverse.linear.m == Mat3::identity().m;
    return pl;
}

void MovingInstances::make_movers(ThreadPool& pool, BackendKind groups) {
    const auto faces = [&](std::size_t k) { return (*meshes_)[instances_[k].mesh].faces.size(); };
    // Instance k joins the run before it when both share a motion that never turns and k's faces
    // follow the run's.
    std::size_t k = 0;
    while (k < instances_.size()) {
        const MovingInstance& head = instances_[k];
        std::size_t end = k + 1, run_faces = faces(k);
        if (never_turns(motions_[head.motion])) {
            while (end < instances_.size() && instances_[end].motion == head.motion &&
                   instances_[end].first_face == head.first_face + run_faces &&
                   run_faces + faces(end) <= kMaxFlatFaces) {
                run_faces += faces(end);
                ++end;
            }
        }
        const auto first = static_cast<std::uint32_t>(k);
        const auto count = static_cast<std::uint32_t>(end - k);
        if (count >= 2 && groups_.size() < kMaxGroups) {
            Group g{head.motion, head.first_face, std::make_unique<SceneGeometry>(), nullptr, {}};
            g.geometry->append_flat(flat_mesh(first, count));
            g.backend = make_backend(groups, *g.geometry, pool);
            g.box = g.geometry->bounds();
            groups_.push_back(std::move(g));
            k = end;
            continue;
        }
        movers_.push_back(count >= 2 ? flatten(first, count, pool) : single(first));
        if (!movers_.back().flat && blas_[head.mesh].nodes.empty() &&
            !(*meshes_)[head.mesh].faces.empty()) {
            blas_[head.mesh] = build_bvh((*meshes_)[head.mesh], BvhBuildConfig{}, pool);
        }
        k = end;
    }
}

MovingInstances::Mover MovingInstances::single(std::uint32_t k) const {
    const MovingInstance& mi = instances_[k];
    const RigidMotion& how = motions_[mi.motion];
    const Aabb& object_box = mesh_bounds_[mi.mesh];
    Mover mv;
    mv.first = k;
    mv.motion = mi.motion;
    mv.still = never_turns(how) && !object_box.empty();
    if (!mv.still) {
        return mv;
    }
    // The mesh's box corners in the motion's frame, turned by its one attitude, and the offset.
    const Quat q = how.at(0.0).attitude;
    double reach = 0.0;
    for (int c = 0; c < 8; ++c) {
        const Vec3d corner((c & 1) ? object_box.hi.x : object_box.lo.x,
                           (c & 2) ? object_box.hi.y : object_box.lo.y,
                           (c & 4) ? object_box.hi.z : object_box.lo.z);
        const Vec3d m = mi.local.apply_point(corner);
        reach = std::max(reach, length(m));
        const Vec3d w = q.rotate(m) + mi.offset_m;
        mv.box_lo = c == 0 ? w : min(mv.box_lo, w);
        mv.box_hi = c == 0 ? w : max(mv.box_hi, w);
    }
    mv.pad_m = 1e-6 * (reach + length(mi.offset_m)) + 1e-6;
    return mv;
}

TriangleMesh MovingInstances::flat_mesh(std::uint32_t first, std::uint32_t count) const {
    TriangleMesh flat;
    // Each copy placed in the motion's frame: offset + attitude * local (the attitude is one).
    const Pose still{{0, 0, 0}, motions_[instances_[first].motion].at(0.0).attitude};
    for (std::uint32_t k = first; k < first + count; ++k) {
        const MovingInstance& mi = instances_[k];
        const TriangleMesh& mesh = (*meshes_)[mi.mesh];
        const Affine3 to_frame = mi.to_world(still);
        TriangleMesh placed;
        placed.faces = mesh.faces;
        placed.vertices.reserve(mesh.vertices.size());
        for (const Vec3f& v : mesh.vertices) {
            placed.vertices.emplace_back(to_frame.apply_point(Vec3d(v)));
        }
        flat.append(placed);
    }
    return flat;
}

MovingInstances::Mover MovingInstances::flatten(std::uint32_t first, std::uint32_t count,
                                                ThreadPool& pool) const {
    Mover mv;
    mv.first = first;
    mv.motion = instances_[first].motion;
    mv.flat = true;
    mv.still = true;
    mv.mesh = flat_mesh(first, count);
    mv.bvh = build_bvh(mv.mesh, BvhBuildConfig{}, pool);
    const Aabb box = mv.mesh.bounds();
    mv.box_lo = Vec3d(box.lo);
    mv.box_hi = Vec3d(box.hi);
    mv.pad_m = 1e-6 * (length(mv.box_lo) + length(mv.box_hi)) + 1e-6;
    return mv;
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

Aabb MovingInstances::swept_box(std::size_t m, double t0, double t1) const {
    const Mover& mv = movers_[m];
    const RigidMotion& how = motions_[mv.motion];
    if (!mv.still) {
        const MovingInstance& mi = instances_[mv.first];
        return mi.swept_bounds(mesh_bounds_[mi.mesh], how, t0, t1);
    }
    // The path's box: its ends and the keys between them (positions are linear between keys).
    Vec3d lo = position_at(mv.motion, t0);
    const Vec3d end = position_at(mv.motion, t1);
    Vec3d hi = max(lo, end);
    lo = min(lo, end);
    const auto first =
        std::upper_bound(how.keys.begin(), how.keys.end(), t0,
                         [](double t, const MotionKey& key) { return t < key.time_s; });
    for (auto key = first; key != how.keys.end() && key->time_s < t1; ++key) {
        lo = min(lo, key->position_m);
        hi = max(hi, key->position_m);
    }
    // A margin for the float rounding of the traced rays, as in MovingInstance::swept_bounds. It
    // is at least 1e-6 of each coordinate's size (|path.lo| + |box_lo|), far above the half
    // float ulp (6e-8 of it) of the conversion below: rounding to the nearest float keeps the
    // box around the part.
    const double pad = mv.pad_m + 1e-6 * (length(hi - lo) + length(lo));
    lo = lo + mv.box_lo - Vec3d{pad, pad, pad};
    hi = hi + mv.box_hi + Vec3d{pad, pad, pad};
    return Aabb{Vec3f(lo), Vec3f(hi)};
}

void MovingInstances::prepare(double t0, double t1, MovingFrame& frame, ThreadPool& pool) const {
    frame.t0 = t0;
    frame.t1 = t1;
    frame.boxes.resize(movers_.size());
    for (std::size_t m = 0; m < movers_.size(); ++m) {
        frame.boxes[m] = swept_box(m, t0, t1);
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

Vec3d MovingInstances::position_at(std::uint32_t motion, double time) const {
    const RigidMotion& how = motions_[motion];
    return how.keys.empty() ? how.pivot_m + how.velocity_mps * time : how.at(time).position_m;
}

bool MovingInstances::to_object(std::size_t k, const detail::TraceRay& world, const Vec3d& org,
                                const Vec3d& dir, double time, detail::TraceRay& local) const {
    const MovingInstance& mi = instances_[k];
    const Placement& pl = placements_[k];
    if (pl.shift_only) {  // only the origin moves: the direction stays the world's
        const Vec3d o =
            org - position_at(mi.motion, time) - mi.offset_m + pl.local_inverse.translation;
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
    local.inv_dir = detail::slab_inverse(local.dir);
    return false;
}

namespace {

/// The watertight set-up of `local` (ray `world` in a mover's coordinates): when the mover only
/// shifts, that of the world direction, made once per ray.
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

/// The nearest hit in one mesh, out of line: the two walks in one function ran slower.
[[gnu::noinline]] bool walk_mesh(const Bvh& bvh, const detail::TraceRay& local,
                                 detail::NearestVisitor& vis) {
    return detail::walk_bvh(bvh, local, vis, [&](std::uint32_t face) { return vis.visit(face); });
}

}  // namespace

void MovingInstances::trace_group(const Group& g, const RayBatch& rays, std::size_t begin,
                                  std::size_t end, std::span<const double> ray_time_s,
                                  MovingFrame& frame, HitBatch& hits) const {
    // A few ulps past the hit found so far: a hit as near on a lower face ID still wins.
    constexpr double kRoom = 1.0 + 8.0 * std::numeric_limits<float>::epsilon();
    const float lo[3] = {g.box.lo.x, g.box.lo.y, g.box.lo.z};
    const float hi[3] = {g.box.hi.x, g.box.hi.y, g.box.hi.z};
    RayBatch& s = frame.shifted;
    s.resize(end - begin);  // then shrunk to the rays kept (the capacity stays for the next block)
    frame.shifted_index.resize(end - begin);
    std::size_t kept = 0;
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3d o = rays.origin(i) - position_at(g.motion, ray_time_s[i - begin]);
        const double tmax = hits.face[i] != kNoFace
                                ? std::min(rays.tmax[i], static_cast<double>(hits.t[i]) * kRoom)
                                : rays.tmax[i];
        // The shifted ray as the backend sees it (float) against the still mesh's box.
        detail::TraceRay r = detail::make_box_ray(rays, i);
        r.org = Vec3f(o);
        float entry = 0.0f;
        if (!detail::slab_entry(r, lo, hi, r.tmin,
                                std::min(r.tmax, static_cast<float>(tmax) * 1.0001f), entry)) {
            continue;
        }
        s.set(kept, o, rays.direction(i), rays.tmin[i], tmax);
        frame.shifted_index[kept++] = i;
    }
    s.resize(kept);
    if (s.empty()) {
        return;
    }
    if (!frame.caller) {
        frame.caller = std::make_unique<ThreadPool>(1);
    }
    HitBatch& gh = frame.group_hits;
    gh.resize(s.size());
    g.backend->intersect(s, 0, s.size(), gh, *frame.caller);
    for (std::size_t j = 0; j < s.size(); ++j) {
        const std::size_t i = frame.shifted_index[j];
        if (gh.face[j] == kNoFace) {
            continue;
        }
        const std::uint32_t face = g.first_face + gh.face[j];
        if (hits.face[i] == kNoFace || gh.t[j] < hits.t[i] ||
            (gh.t[j] == hits.t[i] && face < hits.face[i])) {
            hits.t[i] = gh.t[j];
            hits.face[i] = face;
            hits.u[i] = gh.u[j];
            hits.v[i] = gh.v[j];
        }
    }
}

void MovingInstances::intersect(const RayBatch& rays, std::size_t begin, std::size_t end,
                                std::span<const double> ray_time_s, MovingFrame& frame,
                                HitBatch& hits) const {
    using detail::TraceRay;
    for (const Group& g : groups_) {
        trace_group(g, rays, begin, end, ray_time_s, frame, hits);
    }
    if (movers_.empty()) {
        return;
    }
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
        detail::walk_bvh(frame.top, r, vis, [&](std::uint32_t m) {
            const Aabb& b = frame.boxes[m];  // a leaf's box may hold two movers
            const float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
            float entry = 0.0f;
            if (!detail::slab_entry(r, lo, hi, r.tmin, vis.limit(), entry)) {
                return false;
            }
            const Mover& mv = movers_[m];
            const MovingInstance& mi = instances_[mv.first];
            bool shifted = true;
            if (mv.flat) {  // the motion's frame: the ray shifted by the position at its time
                local.org = Vec3f(org - position_at(mv.motion, time));
                local.dir = r.dir;
                local.inv_dir = r.inv_dir;
                vis.enter(mv.mesh, local, mi.first_face, false);
            } else {
                shifted = to_object(mv.first, r, org, dir, time, local);
                vis.enter((*meshes_)[mi.mesh], local, mi.first_face,
                          placements_[mv.first].mirrored);
            }
            set_up.make(local, shifted);
            return walk_mesh(mv.flat ? mv.bvh : blas_[mi.mesh], local, vis);
        });
        vis.store(hits, i);
    }
}

}  // namespace beamtrace
