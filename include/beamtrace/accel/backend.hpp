// One interface for every ray-tracing backend. Queries take a batch of rays (a range of a
// RayBatch) and run multi-threaded over rays; results never depend on the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/accel/kdtree.hpp"
#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/geometry/ray_triangle.hpp"
#include "beamtrace/geometry/scene_geometry.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

/// The backends of the registry (backend_registry.hpp), which names them, says whether this
/// build has each and how to make it. `embree` exists in every build; make_backend and
/// parse_backend_kind refuse it when beamtrace was built without Embree.
enum class BackendKind : std::uint8_t { brute, kdtree, bvh, embree };

/// True when this build has the Embree backend (BEAMTRACE_HAVE_EMBREE).
[[nodiscard]] constexpr bool embree_available() {
#ifdef BEAMTRACE_HAVE_EMBREE
    return true;
#else
    return false;
#endif
}

/// The backend used unless one is asked for: Embree where this build has it (the fastest, see
/// README "Performance"), else our BVH.
[[nodiscard]] constexpr BackendKind default_backend_kind() {
    return embree_available() ? BackendKind::embree : BackendKind::bvh;
}

/// Help text for --backend options: the backends this build has, "bvh | kdtree | brute | ...".
[[nodiscard]] std::string backend_choices();

/// A backend's name from the registry; throws ConfigError listing the built ones otherwise, and
/// for a backend this build lacks (saying how to get it).
[[nodiscard]] BackendKind parse_backend_kind(std::string_view name);
[[nodiscard]] std::string_view to_string(BackendKind kind);

/// How a backend likes to be fed (the pipeline sizes its batches from these, never from the
/// backend's name).
struct BackendTraits {
    /// Rays per intersect() call that keeps it efficient: a CPU backend a few thousand, a GPU
    /// one millions.
    std::size_t preferred_batch_rays = 4096;
    bool coherent_packets = false;  ///< traces neighbouring rays together (wants coherent order)
    bool asynchronous = false;      ///< works best with batches in flight while others are written
    /// Traces instanced meshes in place (two levels); false: traces a flattened copy of the scene.
    bool instances_natively = false;
};

class Backend {
  public:
    virtual ~Backend() = default;
    [[nodiscard]] virtual BackendKind kind() const = 0;
    /// The traits of this backend's registry entry.
    [[nodiscard]] const BackendTraits& traits() const;

    /// Nearest hit of rays [begin, end) into `hits` (which must hold rays.size() slots). Ties in
    /// range go to the lowest face ID, so every backend gives the same face for the same ray.
    virtual void intersect(const RayBatch& rays, std::size_t begin, std::size_t end, HitBatch& hits,
                           ThreadPool& pool) const = 0;
    /// Nearest hits of rays [begin, end) that come in beams of `rays_per_beam` (rays
    /// [begin + k * rays_per_beam, begin + (k + 1) * rays_per_beam): a pulse's sub-rays, from
    /// one origin in a narrow cone): the hits intersect() gives, bit for bit. The BVH over one
    /// mesh traces a beam's rays as one packet walk; the other backends as intersect().
    virtual void intersect_beams(const RayBatch& rays, std::size_t begin, std::size_t end,
                                 std::size_t rays_per_beam, HitBatch& hits,
                                 ThreadPool& pool) const {
        (void)rays_per_beam;
        intersect(rays, begin, end, hits, pool);
    }
    /// occluded[i] = 1 when ray i meets anything in [tmin, tmax].
    virtual void occluded(const RayBatch& rays, std::size_t begin, std::size_t end,
                          std::vector<std::uint8_t>& occluded, ThreadPool& pool) const = 0;
    /// Every hit of every ray in [tmin, tmax] on the sides allowed by `facing`.
    virtual void intersect_all(const RayBatch& rays, Facing facing, AllHits& hits,
                               ThreadPool& pool) const = 0;

    /// Nearest hits of the whole batch.
    [[nodiscard]] HitBatch intersect(const RayBatch& rays, ThreadPool& pool) const {
        HitBatch hits;
        hits.resize(rays.size());
        intersect(rays, 0, rays.size(), hits, pool);
        return hits;
    }
};

/// Build settings of every backend (each backend reads its own).
struct BackendConfig {
    BvhBuildConfig bvh;
    KdTreeBuildConfig kdtree;
    BvhTraceConfig bvh_trace;  ///< packets or single rays (the BVH backend over one mesh)
};

/// Builds a backend over `mesh`, which must outlive it (geometry is never copied; the Embree
/// backend copies the vertices once into an Embree buffer when the vector has no spare capacity
/// for Embree's 16-byte loads of the last vertex).
[[nodiscard]] std::unique_ptr<Backend> make_backend(BackendKind kind, const TriangleMesh& mesh,
                                                    ThreadPool& pool,
                                                    const BackendConfig& config = {});

/// Builds a backend over instanced geometry, which must outlive it. One mesh placed once is
/// traced exactly as above; otherwise the BVH backend is two-level (a BVH over instances and exact
/// spheres, one per unique mesh: triangles are never copied), Embree places identity instances
/// directly in its top scene and the others as Embree instances of one sub-scene per mesh, with
/// the exact spheres as one native sphere geometry, and brute/kdtree trace a flattened copy and
/// test the spheres one by one. Face IDs are global (SceneGeometry). A sphere hit has u = v = 0.
/// Embree's sphere ranges are its single-precision roots, within about 1e-6 relative of ours.
[[nodiscard]] std::unique_ptr<Backend> make_backend(BackendKind kind, const SceneGeometry& geometry,
                                                    ThreadPool& pool,
                                                    const BackendConfig& config = {});

}  // namespace beamtrace
