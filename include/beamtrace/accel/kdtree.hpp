// k-d trees as plain data, built by the ladar simulator report's rules (section 2.4, Appendix
// A.1/A.5/A.10: split axes cycle x -> y -> z, the split is the cheapest by the surface area
// heuristic among the first, median and last vertex coordinate in the node, leaves hold at most
// 30 triangles or sit at depth 25) or by a proper binned SAH. Triangles that straddle a split go to
// both children. Traversal (in the backend) is exact front-to-back, without the report's 1e-2
// origin nudge.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

#include "beamtrace/core/aabb.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

/// An 8-byte k-d node. Inner: split position, axis and right child (the left child is the next
/// node). Leaf: first entry in prim_ids and face count.
class KdNode {
  public:
    [[nodiscard]] static KdNode leaf(std::uint32_t first, std::uint32_t count) {
        KdNode n;
        n.word_ = first;
        n.bits_ = (count << 2) | 3u;
        return n;
    }
    [[nodiscard]] static KdNode inner(int axis, float split) {
        KdNode n;
        n.word_ = std::bit_cast<std::uint32_t>(split);
        n.bits_ = static_cast<std::uint32_t>(axis);
        return n;
    }
    void set_right(std::uint32_t right) { bits_ = (right << 2) | (bits_ & 3u); }

    [[nodiscard]] bool is_leaf() const { return (bits_ & 3u) == 3u; }
    [[nodiscard]] std::uint32_t axis() const { return bits_ & 3u; }  ///< 0, 1, 2; 3 for a leaf
    [[nodiscard]] float split() const { return std::bit_cast<float>(word_); }
    [[nodiscard]] std::uint32_t right() const { return bits_ >> 2; }
    [[nodiscard]] std::uint32_t first() const { return word_; }
    [[nodiscard]] std::uint32_t count() const { return bits_ >> 2; }

  private:
    std::uint32_t word_ = 0;
    std::uint32_t bits_ = 3;  // an empty leaf
};
static_assert(sizeof(KdNode) == 8, "k-d nodes are 8 bytes");

struct KdTree {
    Aabb bounds;                          ///< the scene's bounds (the root's region)
    std::vector<KdNode> nodes;            ///< nodes[0] is the root
    std::vector<std::uint32_t> prim_ids;  ///< leaf ranges index this; values are face IDs
    int depth = 0;                        ///< deepest level reached (root = 1)
};

/// How a k-d node chooses its split.
enum class KdSplitRule : std::uint8_t {
    /// The report's findKDSplitPlane: the axis cycles x, y, z with depth; the plane is the
    /// cheapest by SAH among the first, median and last vertex coordinate (exact counts instead
    /// of the report's "half on each side" guess); splits continue until max_leaf_size or
    /// max_depth.
    report,
    /// A proper SAH k-d tree: binned SAH over all three axes with a bonus for cutting off empty
    /// space, stopping where a leaf is cheaper than any split.
    sah,
};

struct KdTreeBuildConfig {
    KdSplitRule rule = KdSplitRule::sah;
    /// Nodes at this depth become leaves (root = 1). 0 = automatic: 8 + 1.3 log2(triangles),
    /// the usual choice for SAH trees. At most 60.
    int max_depth = 0;
    int max_leaf_size = 8;           ///< nodes with at most this many triangles become leaves
    float traversal_cost = 1.0f;     ///< SAH cost of a traversal step, relative to...
    float intersection_cost = 2.0f;  ///< ...one ray/triangle test
    float empty_bonus = 0.0f;        ///< sah: cost reduction when one side is empty
    int bin_count = 32;              ///< sah: candidate planes per axis (+1)

    /// The report's settings: rule report, maxD 25, maxN 30, cTrav 1, cIntersect 10.
    [[nodiscard]] static KdTreeBuildConfig report() {
        KdTreeBuildConfig c;
        c.rule = KdSplitRule::report;
        c.max_depth = 25;
        c.max_leaf_size = 30;
        c.traversal_cost = 1.0f;
        c.intersection_cost = 10.0f;
        return c;
    }
};

[[nodiscard]] KdTree build_kdtree(const TriangleMesh& mesh, const KdTreeBuildConfig& config = {});

}  // namespace beamtrace
