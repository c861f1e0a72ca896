// Moving instances (scene parts with a `motion:`), traced at each ray's own time, in two ways:
// - Groups: a run of instances with consecutive face IDs that share a motion that never turns
//   (the copies of an `array:` with a velocity or keys that only move) is, in the motion's frame
//   (scene coordinates less the motion's position p(t)), a still mesh: it is flattened once and
//   given to a backend of the survey's kind (Embree or our BVH). Each ray's origin is shifted by
//   -p(t) at its own time (direction unchanged), so the hit is exact for every pulse, with no
//   per-block rebuild or commit. At most a few groups (each is one pass over the rays).
// - The others (turning parts, lone parts, runs past that cap): a mesh BVH per unique mesh (or
//   the run flattened), built once, and per block of rays a small top-level BVH over their
//   bounds swept over the block's time span, refitted from block to block. Each ray that
//   reaches a box is taken into the part's coordinates with the part placed at that ray's time.
// Either way every pulse sees each part exactly where it is when the pulse is emitted (to float
// precision of the traced coordinates, about 1e-6 of them). The still part of the scene is traced
// by any backend first; intersect() then keeps whichever hit is nearer (ties: lower face ID).
// Blocks share nothing: a block's top level and scratch live in its own MovingFrame.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/geometry/rigid_motion.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

namespace detail {
struct TraceRay;
}  // namespace detail

/// The top level of the moving instances for rays whose times lie in [t0, t1]: a BVH over each
/// instance's bounds swept over that span. One per thread (the survey keeps one per block).
struct MovingFrame {
    double t0 = 0.0, t1 = 0.0;
    std::vector<Aabb> boxes;  ///< per mover (an instance, or a flattened run of them)
    Bvh top;                  ///< prim_ids index the movers
    /// The summed half areas of the top's nodes when it was built: prepare() refits the same
    /// tree to new boxes and builds a new one only when the refitted sum exceeds twice this.
    double built_cost = 0.0;
    /// intersect()'s scratch: the rays shifted into a group's frame that reach its box, the
    /// index of each among the traced rays, their hits, and a pool with no workers (the group's
    /// backend traces on the caller's thread).
    RayBatch shifted;
    std::vector<std::size_t> shifted_index;
    HitBatch group_hits;
    std::unique_ptr<ThreadPool> caller;
};

class MovingInstances {
  public:
    /// Builds a BVH for each mesh that `instances` place. `meshes`, `instances` and `motions`
    /// must outlive this object.
    MovingInstances(const std::vector<TriangleMesh>& meshes,
                    std::span<const MovingInstance> instances, std::span<const RigidMotion> motions,
                    const BvhBuildConfig& config, ThreadPool& pool,
                    BackendKind groups = BackendKind::bvh);

    [[nodiscard]] bool empty() const { return instances_.empty(); }
    [[nodiscard]] std::size_t size() const { return instances_.size(); }

    /// Makes `frame` the top level for times in [t0, t1] (t0 <= t1), on `pool`: the frame's tree
    /// refitted to the instances' new swept boxes, or a new one when the refit has grown loose.
    /// (Hits never depend on the tree's shape, only its speed does.)
    void prepare(double t0, double t1, MovingFrame& frame, ThreadPool& pool) const;

    /// Nearest hits of rays [begin, end) on the moving instances, ray i's instances placed at
    /// time ray_time_s[i - begin] (inside the frame's span), written to `hits` where nearer than
    /// the hit it holds (ties in range: the lower face ID, as in every backend). Runs on the
    /// caller's thread; results depend on nothing but the rays and times.
    void intersect(const RayBatch& rays, std::size_t begin, std::size_t end,
                   std::span<const double> ray_time_s, MovingFrame& frame, HitBatch& hits) const;

  private:
    struct Placement {
        Affine3 local_inverse;  ///< the motion's frame -> object coordinates
        bool mirrored = false;
        /// The part is only shifted (no turn, no linear map): a ray keeps its direction, and its
        /// division and watertight set-up, in the part's object coordinates.
        bool shift_only = false;
    };
    /// A prim of the top level: one instance (its mesh's BVH, the ray taken into its object
    /// coordinates), or a run of instances with consecutive face IDs that share a motion that
    /// never turns (an `array:` of moving copies), flattened once into one mesh in the motion's
    /// frame (scene coordinates less the motion's position at the ray's time): a ray is only
    /// shifted into it and meets the run through one BVH.
    struct Mover {
        std::uint32_t first = 0;  ///< the instance (the run's first)
        std::uint32_t motion = 0;
        bool flat = false;
        TriangleMesh mesh;  ///< flat: the run's faces in the motion's frame, in face ID order
        Bvh bvh;            ///< flat: over `mesh`
        /// The motion never turns the mover: its swept box over a span is the path's box plus
        /// [box_lo, box_hi] (its box in the motion's frame, offsets included) padded by pad_m
        /// and a share of the path's size, computed without the general sweep.
        bool still = false;
        Vec3d box_lo{0, 0, 0}, box_hi{0, 0, 0};
        double pad_m = 0.0;
    };
    /// A run of instances with consecutive face IDs that share a motion that never turns,
    /// flattened into one still mesh in the motion's frame and traced by a backend of the
    /// survey's kind: each ray's origin shifted by the motion's position at the ray's time.
    struct Group {
        std::uint32_t motion = 0;
        std::uint32_t first_face = 0;
        std::unique_ptr<SceneGeometry> geometry;  ///< the backend points into it
        std::unique_ptr<Backend> backend;
        Aabb box;  ///< of the still mesh: only rays that reach it go to the backend
    };
    /// Nearest hits of rays [begin, end) on group g, merged into `hits`.
    void trace_group(const Group& g, const RayBatch& rays, std::size_t begin, std::size_t end,
                     std::span<const double> ray_time_s, MovingFrame& frame, HitBatch& hits) const;
    /// Instances [first, first + count) placed in their motion's frame, as one mesh.
    [[nodiscard]] TriangleMesh flat_mesh(std::uint32_t first, std::uint32_t count) const;
    [[nodiscard]] static Placement place(const MovingInstance& mi, const RigidMotion& how);
    /// Makes movers_: the runs that share a still motion flattened, the other instances alone.
    void make_movers(ThreadPool& pool, BackendKind groups);
    [[nodiscard]] Mover single(std::uint32_t k) const;
    [[nodiscard]] Mover flatten(std::uint32_t first, std::uint32_t count, ThreadPool& pool) const;
    /// Mover m's bounds over [t0, t1].
    [[nodiscard]] Aabb swept_box(std::size_t m, double t0, double t1) const;
    /// The position of motion `motion` at `time`.
    [[nodiscard]] Vec3d position_at(std::uint32_t motion, double time) const;
    /// The world ray `world` (org, dir in double) at `time` in instance k's object coordinates:
    /// origin, direction and inverse direction of `local` (not its watertight set-up). True
    /// when the part only shifts (the direction is the world's).
    bool to_object(std::size_t k, const detail::TraceRay& world, const Vec3d& org, const Vec3d& dir,
                   double time, detail::TraceRay& local) const;
    const std::vector<TriangleMesh>* meshes_;
    std::span<const MovingInstance> instances_;
    std::span<const RigidMotion> motions_;
    std::vector<Bvh> blas_;              ///< per mesh (empty for meshes no instance moves)
    std::vector<Aabb> mesh_bounds_;      ///< per mesh, object coordinates
    std::vector<Placement> placements_;  ///< per instance
    std::vector<Mover> movers_;          ///< the top level's prims
    std::vector<Group> groups_;          ///< traced before the top level
    BvhBuildConfig top_config_;
};

}  // namespace beamtrace
