// Bounding volume hierarchy as plain data: flattened 32-byte nodes (siblings stored next to each
// other) and a permutation of face IDs. The geometry stays in the TriangleMesh.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

struct BvhNode {
    float lo[3];  ///< bounds, minimum corner
    std::uint32_t
        index;    ///< inner: left child (the right child is the next node); leaf: first prim
    float hi[3];  ///< bounds, maximum corner
    std::uint32_t count;  ///< number of faces in a leaf; 0 for an inner node

    [[nodiscard]] bool is_leaf() const { return count != 0; }
};
static_assert(sizeof(BvhNode) == 32, "BVH nodes are 32 bytes");

struct Bvh {
    std::vector<BvhNode> nodes;           ///< nodes[0] is the root (absent for an empty mesh)
    std::vector<std::uint32_t> prim_ids;  ///< leaf ranges index this; values are face IDs
    int depth = 0;                        ///< longest root-to-leaf path (root = 1)
};

struct BvhBuildConfig {
    int bin_count = 16;              ///< SAH bins per axis
    int min_leaf_size = 4;           ///< a node with at most this many faces is a leaf
    int max_leaf_size = 8;           ///< a node with more faces is always split (if it can be)
    float traversal_cost = 1.0f;     ///< SAH cost of visiting a node, relative to...
    float intersection_cost = 1.0f;  ///< ...the cost of one ray/triangle test
};

/// How the BVH backend traces nearest hits (Backend::intersect) over one mesh. Packets give the
/// same hits as single rays, bit for bit (t, face, u, v): only the speed differs.
enum class BvhPackets : std::uint8_t {
    automatic,  ///< packets where neighbouring rays are coherent (see max_spread_rad), else single
    off,        ///< one ray at a time
    always,     ///< every ray in a packet, coherent or not (for tests)
};

struct BvhTraceConfig {
    BvhPackets packets = BvhPackets::automatic;
    /// Rays per packet: 0 = the widest this CPU has (16 with AVX-512, 8 with AVX2, else single
    /// rays); 8 or 16 ask for that width, and fall back to single rays where the CPU lacks it.
    int lanes = 0;
    /// automatic: a packet is traced together when every direction is within this angle of its
    /// first ray's (and all share the watertight test's axis order), else ray by ray.
    double max_spread_rad = 0.15;
};

/// The packet width the BVH backend traces with under `config` on this CPU: 16 or 8, or 1 (one
/// ray at a time: packets off, or no AVX2).
[[nodiscard]] int bvh_packet_lanes(const BvhTraceConfig& config);

/// Top-down binned-SAH build (Wald 2007). `pool` parallelises the per-face preparation and the
/// subtrees below the top levels; the result is the same for any thread count.
[[nodiscard]] Bvh build_bvh(const TriangleMesh& mesh, const BvhBuildConfig& config,
                            ThreadPool& pool);

/// The same over arbitrary primitive boxes (e.g. instances); prim_ids index `boxes`.
[[nodiscard]] Bvh build_bvh(std::span<const Aabb> boxes, const BvhBuildConfig& config,
                            ThreadPool& pool);

}  // namespace beamtrace
