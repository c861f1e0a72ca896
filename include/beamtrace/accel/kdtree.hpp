// The ladar simulator report's k-d tree (section 2.4, Appendix A.1/A.5/A.10) as plain data:
// split axes cycle x -> y -> z, the split position is the cheapest by the surface area heuristic
// among the first, median and last vertex coordinate in the node, leaves hold at most 30
// triangles or sit at depth 25. Triangles that straddle a split go to both children.
// Traversal (in the backend) is exact front-to-back, without the report's 1e-2 origin nudge.
#pragma once

#include <cstdint>
#include <vector>

#include "beamtrace/core/aabb.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

struct KdNode {
    float split = 0.0f;       ///< inner: split-plane position along `axis`
    std::uint32_t index = 0;  ///< inner: right child (the left child is the next node); leaf: first
                              ///< entry in prim_ids
    std::uint32_t count = 0;  ///< leaf: number of faces
    std::uint32_t axis = 3;   ///< 0, 1, 2 for x, y, z; 3 for a leaf

    [[nodiscard]] bool is_leaf() const { return axis == 3; }
};
static_assert(sizeof(KdNode) == 16, "k-d nodes are 16 bytes");

struct KdTree {
    Aabb bounds;                          ///< the scene's bounds (the root's region)
    std::vector<KdNode> nodes;            ///< nodes[0] is the root
    std::vector<std::uint32_t> prim_ids;  ///< leaf ranges index this; values are face IDs
    int depth = 0;                        ///< deepest level reached (root = 1)
};

struct KdTreeBuildConfig {
    int max_depth = 25;               ///< the report's maxD: nodes at this depth are leaves
    int max_leaf_size = 30;           ///< the report's maxN
    float traversal_cost = 1.0f;      ///< the report's cTrav
    float intersection_cost = 10.0f;  ///< the report's cIntersect
    /// Stop splitting when the best candidate costs more than a leaf (not in the report, which
    /// splits until maxN or maxD; splits that separate nothing are never made either way).
    bool sah_termination = true;
};

[[nodiscard]] KdTree build_kdtree(const TriangleMesh& mesh, const KdTreeBuildConfig& config = {});

}  // namespace beamtrace
