// The three own backends: brute force (the oracle), the report's k-d tree and the binned-SAH BVH
// (single-level over one mesh, or two-level over instanced meshes and exact spheres); Embree is
// in embree_backend.cpp, the table naming them all in backend_registry.cpp.
#include <cmath>
#include <memory>
#include <span>
#include <string>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/accel/kdtree.hpp"
#include "beamtrace/core/error.hpp"
#include "detail/own_backends.hpp"
#include "detail/packet_trace.hpp"
#include "detail/queries.hpp"
#include "detail/walk_bvh.hpp"

namespace beamtrace::detail {
namespace {

using detail::slab_entry;
using detail::TraceRay;

constexpr float kPad = 2.0f * 3.0f * std::numeric_limits<float>::epsilon();

/// Visits every exact sphere of `spheres` (may be null) in turn; true when the visitor stops.
template <class Visitor>
bool visit_spheres(const std::vector<ExactSphere>* spheres, const TraceRay& ray, Visitor& vis) {
    if (spheres != nullptr) {
        for (const ExactSphere& s : *spheres) {
            if (vis.visit_sphere(s, ray)) {
                return true;
            }
        }
    }
    return false;
}

struct BruteForceTraverser {
    const TriangleMesh* mesh = nullptr;
    const std::vector<ExactSphere>* spheres = nullptr;  ///< tested one by one before the mesh

    template <class Visitor>
    void traverse(const TraceRay& ray, Visitor& vis) const {
        if (visit_spheres(spheres, ray, vis)) {
            return;
        }
        vis.enter(*mesh, ray, 0, false);
        const auto face_count = static_cast<std::uint32_t>(mesh->triangle_count());
        for (std::uint32_t f = 0; f < face_count; ++f) {
            if (vis.visit(f)) {
                return;
            }
        }
    }
};

struct BvhTraverser {
    const TriangleMesh* mesh = nullptr;
    Bvh bvh;
    BvhTraceConfig trace;
    int lanes = 1;  ///< packet_lanes(trace) on this CPU; 1: one ray at a time

    /// Nearest hits of rays [begin, end): in packets where they are coherent (packet_trace.hpp).
    void intersect_range(const RayBatch& rays, std::size_t begin, std::size_t end,
                         HitBatch& hits) const {
        intersect_packets(bvh, *mesh, rays, begin, end, hits, lanes,
                          trace.packets != BvhPackets::always, trace.max_spread_rad);
    }

    /// The same for rays in beams of `rays_per_beam` (intersect_beams in packet_trace.hpp).
    void intersect_beams_range(const RayBatch& rays, std::size_t begin, std::size_t end,
                               std::size_t rays_per_beam, HitBatch& hits) const {
        intersect_beams(bvh, *mesh, rays, begin, end, rays_per_beam, hits, lanes,
                        trace.packets != BvhPackets::always, trace.max_spread_rad);
    }

    template <class Visitor>
    void traverse(const TraceRay& r, Visitor& vis) const {
        vis.enter(*mesh, r, 0, false);
        walk_bvh(bvh, r, vis, [&](std::uint32_t face) { return vis.visit(face); });
    }
};

/// Two-level BVH: a top-level BVH over instance bounds and exact spheres (prims past the last
/// instance), and one BVH per unique mesh.
struct TwoLevelTraverser {
    struct Instance {
        std::uint32_t mesh;
        std::uint32_t first_face;
        bool identity;
        bool mirrored;
        Affine3 to_object;
    };
    const SceneGeometry* geometry = nullptr;
    Bvh top;
    std::vector<Bvh> blas;  // per mesh
    std::vector<Instance> instances;

    template <class Visitor>
    void traverse(const TraceRay& r, Visitor& vis) const {
        walk_bvh(top, r, vis, [&](std::uint32_t k) {
            if (k >= instances.size()) {
                return vis.visit_sphere(geometry->spheres[k - instances.size()], r);
            }
            const Instance& inst = instances[k];
            const TriangleMesh& mesh = geometry->meshes[inst.mesh];
            if (inst.identity) {
                vis.enter(mesh, r, inst.first_face, false);
                return walk_bvh(blas[inst.mesh], r, vis,
                                [&](std::uint32_t face) { return vis.visit(face); });
            }
            const TraceRay local = to_object(r, inst.to_object);
            vis.enter(mesh, local, inst.first_face, inst.mirrored);
            return walk_bvh(blas[inst.mesh], local, vis,
                            [&](std::uint32_t face) { return vis.visit(face); });
        });
    }
};

TwoLevelTraverser build_two_level(const SceneGeometry& geometry, const BvhBuildConfig& config,
                                  ThreadPool& pool) {
    TwoLevelTraverser t;
    t.geometry = &geometry;
    t.blas.reserve(geometry.meshes.size());
    for (const auto& mesh : geometry.meshes) {
        t.blas.push_back(build_bvh(mesh, config, pool));
    }
    std::vector<Aabb> boxes(geometry.instances.size() + geometry.spheres.size());
    t.instances.reserve(geometry.instances.size());
    for (std::size_t k = 0; k < geometry.instances.size(); ++k) {
        const MeshInstance& mi = geometry.instances[k];
        boxes[k] = geometry.instance_bounds(k);
        t.instances.push_back({mi.mesh, mi.first_face, mi.to_world.is_identity(),
                               mi.to_world.determinant() < 0.0, mi.to_world.inverse()});
    }
    for (std::size_t k = 0; k < geometry.spheres.size(); ++k) {
        boxes[geometry.instances.size() + k] = SceneGeometry::sphere_bounds(geometry.spheres[k]);
    }
    BvhBuildConfig top_config = config;
    top_config.min_leaf_size = 1;
    top_config.max_leaf_size = 2;
    t.top = build_bvh(std::span<const Aabb>(boxes), top_config, pool);
    return t;
}

struct KdTreeTraverser {
    const TriangleMesh* mesh = nullptr;
    KdTree tree;
    const std::vector<ExactSphere>* spheres = nullptr;  ///< tested one by one before the tree

    template <class Visitor>
    void traverse(const TraceRay& r, Visitor& vis) const {
        if (visit_spheres(spheres, r, vis)) {
            return;
        }
        vis.enter(*mesh, r, 0, false);
        if (tree.prim_ids.empty()) {
            return;
        }
        const float lo[3] = {tree.bounds.lo.x, tree.bounds.lo.y, tree.bounds.lo.z};
        const float hi[3] = {tree.bounds.hi.x, tree.bounds.hi.y, tree.bounds.hi.z};
        float tnear = 0.0f, tfar = 0.0f;
        if (!detail::slab_interval(r, lo, hi, r.tmin, vis.limit(), tnear, tfar)) {
            return;
        }
        struct Entry {
            std::uint32_t node;
            float tnear, tfar;
        };
        Entry stack[64];
        int sp = 0;
        const KdNode* nodes = tree.nodes.data();
        std::uint32_t index = 0;
        for (;;) {
            const KdNode& node = nodes[index];
            if (node.is_leaf()) {
                for (std::uint32_t k = node.first(); k < node.first() + node.count(); ++k) {
                    if (vis.visit(tree.prim_ids[k])) {
                        return;
                    }
                }
            } else {
                const auto a = static_cast<std::size_t>(node.axis());
                const float split = node.split();
                const float o = r.org[a];
                const std::uint32_t left = index + 1, right = node.right();
                if (o == split) {
                    // Starting on the plane: both sides, whole interval (rare, and exact).
                    stack[sp++] = {right, tnear, tfar};
                    index = left;
                    continue;
                }
                const std::uint32_t near_child = o < split ? left : right;
                const std::uint32_t far_child = o < split ? right : left;
                const float t_split = (split - o) * r.inv_dir[a];
                // Moving away from the plane, or parallel to it: only the near side.
                if (!(t_split > 0.0f) || t_split == std::numeric_limits<float>::infinity()) {
                    index = near_child;
                    continue;
                }
                const float ts_lo = t_split - t_split * kPad;
                const float ts_hi = t_split + t_split * kPad;
                if (ts_lo > tfar) {
                    index = near_child;  // leaves this node before reaching the plane
                    continue;
                }
                if (ts_hi < tnear) {
                    index = far_child;  // crossed the plane before entering this node
                    continue;
                }
                stack[sp++] = {far_child, std::max(tnear, ts_lo), tfar};
                tfar = std::min(tfar, ts_hi);
                index = near_child;
                continue;
            }
            for (;;) {
                if (sp == 0) {
                    return;
                }
                const Entry e = stack[--sp];
                if (e.tnear <= vis.limit()) {
                    index = e.node;
                    tnear = e.tnear;
                    tfar = e.tfar;
                    break;
                }
            }
        }
    }
};

}  // namespace

std::unique_ptr<Backend> make_brute_backend(const TriangleMesh& mesh, ThreadPool& /*pool*/,
                                            const BackendConfig& /*config*/) {
    return std::make_unique<QueryBackend<BruteForceTraverser, BackendKind::brute>>(
        BruteForceTraverser{&mesh});
}

std::unique_ptr<Backend> make_kdtree_backend(const TriangleMesh& mesh, ThreadPool& /*pool*/,
                                             const BackendConfig& config) {
    return std::make_unique<QueryBackend<KdTreeTraverser, BackendKind::kdtree>>(
        KdTreeTraverser{&mesh, build_kdtree(mesh, config.kdtree)});
}

std::unique_ptr<Backend> make_bvh_backend(const TriangleMesh& mesh, ThreadPool& pool,
                                          const BackendConfig& config) {
    return std::make_unique<QueryBackend<BvhTraverser, BackendKind::bvh>>(
        BvhTraverser{&mesh, build_bvh(mesh, config.bvh, pool), config.bvh_trace,
                     packet_lanes(config.bvh_trace)});
}

/// The meshes of `geometry` in one, vertices copied bit for bit, when every instance is placed
/// with the identity and there are no exact spheres (face IDs stay the same: instances are
/// sorted by first face and their ranges follow one another); nullptr otherwise. The one-mesh
/// walk then meets the same world ray and the same float corners as the two-level walk, so
/// its hits are the same bits, and it traces coherent rays in packets.
std::shared_ptr<const TriangleMesh> identity_meshes_in_one(const SceneGeometry& geometry) {
    if (!geometry.spheres.empty() || geometry.instances.size() < 2) {
        return nullptr;
    }
    auto flat = std::make_shared<TriangleMesh>();
    for (const MeshInstance& inst : geometry.instances) {
        if (!inst.to_world.is_identity() || inst.first_face != flat->faces.size()) {
            return nullptr;
        }
        const TriangleMesh& m = geometry.meshes[inst.mesh];
        if (flat->vertices.size() + m.vertices.size() >= kNoFace) {
            return nullptr;
        }
        flat->append(m);
    }
    return flat;
}

std::unique_ptr<Backend> make_bvh_backend(const SceneGeometry& geometry, ThreadPool& pool,
                                          const BackendConfig& config) {
    if (auto flat = identity_meshes_in_one(geometry)) {
        const TriangleMesh& mesh = *flat;
        return std::make_unique<QueryBackend<BvhTraverser, BackendKind::bvh>>(
            BvhTraverser{&mesh, build_bvh(mesh, config.bvh, pool), config.bvh_trace,
                         packet_lanes(config.bvh_trace)},
            std::move(flat));
    }
    return std::make_unique<QueryBackend<TwoLevelTraverser, BackendKind::bvh>>(
        build_two_level(geometry, config.bvh, pool));
}

// The oracle backends trace a flattened copy (face IDs are the same) and test the exact spheres
// one by one.
std::unique_ptr<Backend> make_brute_backend(const SceneGeometry& geometry, ThreadPool& /*pool*/,
                                            const BackendConfig& /*config*/) {
    auto flat = std::make_shared<const TriangleMesh>(geometry.flatten());
    const auto* spheres = geometry.spheres.empty() ? nullptr : &geometry.spheres;
    return std::make_unique<QueryBackend<BruteForceTraverser, BackendKind::brute>>(
        BruteForceTraverser{flat.get(), spheres}, flat);
}

std::unique_ptr<Backend> make_kdtree_backend(const SceneGeometry& geometry, ThreadPool& /*pool*/,
                                             const BackendConfig& config) {
    auto flat = std::make_shared<const TriangleMesh>(geometry.flatten());
    const auto* spheres = geometry.spheres.empty() ? nullptr : &geometry.spheres;
    return std::make_unique<QueryBackend<KdTreeTraverser, BackendKind::kdtree>>(
        KdTreeTraverser{flat.get(), build_kdtree(*flat, config.kdtree), spheres}, flat);
}

}  // namespace beamtrace::detail
