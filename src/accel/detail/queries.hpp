// The three ray queries (nearest, any, all), written once over a traverser. A traverser has
//   template <class Visitor> void traverse(const TraceRay&, Visitor&) const;
// calls `visitor.enter(mesh, ray, face_offset, mirrored)` for each mesh it descends into, then
// `visitor.visit(local_face)` for candidate faces, and `visitor.visit_sphere(sphere, world_ray)`
// for candidate exact spheres, skipping nodes farther than `visitor.limit()`, and stops when a
// visit returns true.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <utility>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/geometry/ray_sphere.hpp"
#include "trace_ray.hpp"

namespace beamtrace::detail {

/// Rays per work item: 1024 for large batches, smaller so small batches still use every thread.
[[nodiscard]] inline std::size_t ray_grain(std::size_t rays, const ThreadPool& pool) {
    return std::clamp<std::size_t>(rays / (8 * std::size_t{pool.size()}), 16, 1024);
}

/// Where the ray's line meets an exact sphere, as floats: the roots are worked out in double
/// from the float ray (the same arithmetic in every backend). False when the line misses.
[[nodiscard]] inline bool sphere_roots(const TraceRay& r, const ExactSphere& s, float& t_enter,
                                       float& t_exit) {
    const auto iv = intersect_sphere_line(Vec3d(r.org), Vec3d(r.dir),
                                          Sphere{Vec3d(s.center), static_cast<double>(s.radius)});
    if (!iv) {
        return false;
    }
    t_enter = static_cast<float>(iv->t_enter);
    t_exit = static_cast<float>(iv->t_exit);
    return true;
}

/// The nearest hit's limit is its range times this (a few ulps past it; see NearestVisitor).
inline constexpr float kNearestRoom = 1.0f + 8.0f * std::numeric_limits<float>::epsilon();

/// What every visitor keeps of the mesh it is in: a traverser calls enter() before it visits
/// faces of a mesh (with the ray in that mesh's coordinates, the global ID of its face 0, and
/// whether its placement mirrors, which swaps front and back).
class VisitorBase {
  public:
    void enter(const TriangleMesh& mesh, const TraceRay& ray, std::uint32_t face_offset,
               bool mirrored) {
        mesh_ = &mesh;
        ray_ = &ray;
        offset_ = face_offset;
        mirrored_ = mirrored;
    }

  protected:
    bool test(std::uint32_t face, float tmax, Facing facing, TriangleHit& h) const {
        const Face& f = mesh_->faces[face];
        return intersect_watertight(ray_->wt, mesh_->vertices[f[0]], mesh_->vertices[f[1]],
                                    mesh_->vertices[f[2]], ray_->tmin, tmax, facing, h);
    }
    const TriangleMesh* mesh_ = nullptr;
    const TraceRay* ray_ = nullptr;
    std::uint32_t offset_ = 0;
    bool mirrored_ = false;
};

/// The nearest hit: the least range as the triangle test divides it out, then the lowest face
/// ID, whatever order the faces come in. The triangle test clips on T before its division by
/// det, and traversers clip boxes at an entry computed to an ulp or two: with the best range
/// itself as their limit, either could drop a hit at that very range (a point on an edge two
/// triangles share), so the limit they get is a few ulps past it and the choice is made here.
class NearestVisitor : public VisitorBase {
    static constexpr float kRoom = kNearestRoom;

  public:
    explicit NearestVisitor(const TraceRay& ray) : best_t_(ray.tmax), limit_(ray.tmax * kRoom) {}
    [[nodiscard]] float limit() const { return limit_; }
    /// Starts from slot i of `hits` (a nearest hit of the same ray found elsewhere, or a miss),
    /// so that only nearer hits, or hits as near on a lower face ID, replace it.
    void start_from(const HitBatch& hits, std::size_t i) {
        if (hits.face[i] != kNoFace && hits.t[i] <= best_t_) {
            keep(hits.t[i], hits.face[i], hits.u[i], hits.v[i]);
        }
    }
    bool visit(std::uint32_t local_face) {
        TriangleHit h;
        const std::uint32_t face = offset_ + local_face;
        if (test(local_face, limit_, Facing::both, h) &&
            (h.t < best_t_ || (h.t == best_t_ && face < face_))) {
            keep(h.t, face, h.u, h.v);
        }
        return false;
    }
    bool visit_sphere(const ExactSphere& s, const TraceRay& world) {
        float t0 = 0, t1 = 0;
        if (!sphere_roots(world, s, t0, t1)) {
            return false;
        }
        const float t = t0 >= world.tmin ? t0 : t1;
        if (t >= world.tmin && t <= best_t_ && (t < best_t_ || s.face < face_)) {
            keep(t, s.face, 0.0f, 0.0f);
        }
        return false;
    }
    void store(HitBatch& hits, std::size_t i) const {
        if (face_ != kNoFace) {
            hits.t[i] = best_t_;
            hits.face[i] = face_;
            hits.u[i] = u_;
            hits.v[i] = v_;
        } else {
            hits.t[i] = std::numeric_limits<float>::infinity();
            hits.face[i] = kNoFace;
            hits.u[i] = hits.v[i] = 0.0f;
        }
    }

  private:
    void keep(float t, std::uint32_t face, float u, float v) {
        best_t_ = t;
        limit_ = t * kRoom;
        face_ = face;
        u_ = u;
        v_ = v;
    }
    float best_t_;
    float limit_;  ///< best_t_ and a few ulps: what the triangle test and the traverser clip at
    std::uint32_t face_ = kNoFace;
    float u_ = 0, v_ = 0;
};

class AnyVisitor : public VisitorBase {
  public:
    explicit AnyVisitor(const TraceRay& ray) : tmax_(ray.tmax) {}
    [[nodiscard]] float limit() const { return tmax_; }
    bool visit(std::uint32_t local_face) {
        TriangleHit h;
        hit_ = test(local_face, tmax_, Facing::both, h);
        return hit_;
    }
    bool visit_sphere(const ExactSphere& s, const TraceRay& world) {
        float t0 = 0, t1 = 0;
        hit_ = sphere_roots(world, s, t0, t1) &&
               ((t0 >= world.tmin && t0 <= tmax_) || (t1 >= world.tmin && t1 <= tmax_));
        return hit_;
    }
    [[nodiscard]] bool hit() const { return hit_; }

  private:
    float tmax_;
    bool hit_ = false;
};

struct AllHit {
    float t;
    std::uint32_t face;
    std::uint8_t front;
};

/// Sorts the hits of one ray, out[first..], by (t, face) and drops duplicates (a face met twice at
/// the same range, from two leaves; a sphere's entry and exit differ in range).
inline void sort_unique_hits(std::vector<AllHit>& out, std::size_t first) {
    const auto b = out.begin() + static_cast<std::ptrdiff_t>(first);
    std::sort(b, out.end(), [](const AllHit& x, const AllHit& y) {
        return x.t < y.t || (x.t == y.t && x.face < y.face);
    });
    out.erase(std::unique(
                  b, out.end(),
                  [](const AllHit& x, const AllHit& y) { return x.face == y.face && x.t == y.t; }),
              out.end());
}

/// Packs per-chunk hit lists (chunks in ray order) and per-ray counts into `hits` (CSR).
inline void gather_all_hits(const std::vector<std::vector<AllHit>>& per_chunk,
                            const std::vector<std::uint32_t>& counts, AllHits& hits) {
    const std::size_t n = counts.size();
    hits.offsets.assign(n + 1, 0);
    std::partial_sum(counts.begin(), counts.end(), hits.offsets.begin() + 1);
    const std::size_t total = hits.offsets[n];
    hits.t.resize(total);
    hits.face.resize(total);
    hits.front.resize(total);
    std::size_t k = 0;
    for (const auto& chunk : per_chunk) {
        for (const auto& h : chunk) {
            hits.t[k] = h.t;
            hits.face[k] = h.face;
            hits.front[k] = h.front;
            ++k;
        }
    }
}

class AllVisitor : public VisitorBase {
  public:
    AllVisitor(const TraceRay& ray, Facing facing, std::vector<AllHit>& out)
        : tmax_(ray.tmax), facing_(facing), out_(out), first_(out.size()) {}
    [[nodiscard]] float limit() const { return tmax_; }
    bool visit(std::uint32_t local_face) {
        TriangleHit h;
        Facing facing = facing_;
        if (mirrored_ && facing != Facing::both) {
            facing = facing == Facing::front ? Facing::back : Facing::front;
        }
        if (test(local_face, tmax_, facing, h)) {
            const bool front = h.front != mirrored_;
            out_.push_back({h.t, offset_ + local_face, static_cast<std::uint8_t>(front ? 1 : 0)});
        }
        return false;
    }
    /// A sphere's entry is its front side and its exit its back (one front hit when tangent).
    bool visit_sphere(const ExactSphere& s, const TraceRay& world) {
        float t0 = 0, t1 = 0;
        if (!sphere_roots(world, s, t0, t1)) {
            return false;
        }
        const auto in_range = [&](float t) { return t >= world.tmin && t <= tmax_; };
        if (facing_ != Facing::back && in_range(t0)) {
            out_.push_back({t0, s.face, 1});
        }
        if (facing_ != Facing::front && in_range(t1) && t1 != t0) {
            out_.push_back({t1, s.face, 0});
        }
        return false;
    }
    /// Sorts this ray's hits by (t, face) and drops duplicates (a face met in several leaves).
    void finish() { sort_unique_hits(out_, first_); }

  private:
    float tmax_;
    Facing facing_;
    std::vector<AllHit>& out_;
    std::size_t first_;
};

/// A Backend over any traverser; the only virtual call is per batch.
template <class Traverser, BackendKind Kind>
class QueryBackend final : public Backend {
  public:
    /// `owned` keeps alive geometry that the traverser points into (e.g. a flattened copy).
    explicit QueryBackend(Traverser traverser, std::shared_ptr<const void> owned = nullptr)
        : owned_(std::move(owned)), traverser_(std::move(traverser)) {}

    [[nodiscard]] BackendKind kind() const override { return Kind; }
    [[nodiscard]] const Traverser& traverser() const { return traverser_; }

    void intersect(const RayBatch& rays, std::size_t begin, std::size_t end, HitBatch& hits,
                   ThreadPool& pool) const override {
        if constexpr (requires { traverser_.intersect_range(rays, begin, end, hits); }) {
            // The traverser traces ranges of neighbouring rays itself (e.g. in packets).
            pool.parallel_for(end - begin, ray_grain(end - begin, pool),
                              [&](std::size_t b, std::size_t e) {
                                  traverser_.intersect_range(rays, begin + b, begin + e, hits);
                              });
            return;
        }
        for_each_ray(rays, begin, end, pool, [&](std::size_t i, const TraceRay& r) {
            NearestVisitor vis(r);
            traverser_.traverse(r, vis);
            vis.store(hits, i);
        });
    }

    void intersect_beams(const RayBatch& rays, std::size_t begin, std::size_t end,
                         std::size_t rays_per_beam, HitBatch& hits,
                         ThreadPool& pool) const override {
        if constexpr (requires {
                          traverser_.intersect_beams_range(rays, begin, end, rays_per_beam, hits);
                      }) {
            // Whole beams to each chunk.
            const std::size_t per = std::max<std::size_t>(1, rays_per_beam);
            const std::size_t beams = (end - begin + per - 1) / per;
            const std::size_t grain = std::max<std::size_t>(1, ray_grain(end - begin, pool) / per);
            pool.parallel_for(beams, grain, [&](std::size_t b, std::size_t e) {
                traverser_.intersect_beams_range(rays, begin + b * per,
                                                 std::min(end, begin + e * per), per, hits);
            });
            return;
        }
        intersect(rays, begin, end, hits, pool);
    }

    void occluded(const RayBatch& rays, std::size_t begin, std::size_t end,
                  std::vector<std::uint8_t>& occluded, ThreadPool& pool) const override {
        occluded.resize(rays.size());
        for_each_ray(rays, begin, end, pool, [&](std::size_t i, const TraceRay& r) {
            AnyVisitor vis(r);
            traverser_.traverse(r, vis);
            occluded[i] = vis.hit() ? 1 : 0;
        });
    }

    void intersect_all(const RayBatch& rays, Facing facing, AllHits& hits,
                       ThreadPool& pool) const override {
        const std::size_t n = rays.size();
        const std::size_t grain = ray_grain(n, pool);
        const std::size_t chunks = (n + grain - 1) / grain;
        std::vector<std::vector<AllHit>> per_chunk(chunks);
        std::vector<std::uint32_t> counts(n, 0);
        pool.parallel_for(n, grain, [&](std::size_t b, std::size_t e) {
            auto& out = per_chunk[b / grain];
            for (std::size_t i = b; i < e; ++i) {
                const TraceRay r = make_trace_ray(rays, i);
                const std::size_t before = out.size();
                AllVisitor vis(r, facing, out);
                traverser_.traverse(r, vis);
                vis.finish();
                counts[i] = static_cast<std::uint32_t>(out.size() - before);
            }
        });
        gather_all_hits(per_chunk, counts, hits);
    }

  private:
    /// Calls fn(i, trace ray of i) for rays [begin, end), in parallel chunks.
    template <class Fn>
    static void for_each_ray(const RayBatch& rays, std::size_t begin, std::size_t end,
                             ThreadPool& pool, const Fn& fn) {
        pool.parallel_for(end - begin, ray_grain(end - begin, pool),
                          [&](std::size_t b, std::size_t e) {
                              for (std::size_t i = begin + b; i < begin + e; ++i) {
                                  fn(i, make_trace_ray(rays, i));
                              }
                          });
    }

    std::shared_ptr<const void> owned_;
    Traverser traverser_;
};

}  // namespace beamtrace::detail
