// Invariants of the acceleration structures themselves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/accel/kdtree.hpp"
#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(Bvh, EveryFaceInExactlyOneLeafAndBoundsContainChildren) {
    const TriangleMesh mesh = test::make_icosphere(4, 5.0f);
    ThreadPool pool(2);
    const Bvh bvh = build_bvh(mesh, {}, pool);
    std::vector<int> seen(mesh.triangle_count(), 0);
    std::size_t leaves = 0;
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
        const BvhNode& n = bvh.nodes[i];
        if (n.is_leaf()) {
            ++leaves;
            EXPECT_LE(n.count, 8u);
            for (std::uint32_t k = n.index; k < n.index + n.count; ++k) {
                const std::uint32_t f = bvh.prim_ids[k];
                ++seen[f];
                const Aabb tb = mesh.triangle_bounds(f);
                for (std::size_t a = 0; a < 3; ++a) {
                    EXPECT_LE(n.lo[a], tb.lo[a]);
                    EXPECT_GE(n.hi[a], tb.hi[a]);
                }
            }
        } else {
            for (std::uint32_t c : {n.index, n.index + 1}) {
                ASSERT_LT(c, bvh.nodes.size());
                for (std::size_t a = 0; a < 3; ++a) {
                    EXPECT_LE(n.lo[a], bvh.nodes[c].lo[a]);
                    EXPECT_GE(n.hi[a], bvh.nodes[c].hi[a]);
                }
            }
        }
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }));
    EXPECT_EQ(bvh.nodes.size(), 2 * leaves - 1);

    EXPECT_GT(bvh.depth, 5);
}

TEST(Bvh, ParallelBuildGivesTheSameTreeForAnyThreadCount) {
    const TriangleMesh mesh = test::make_grid(250);  // 125000 triangles: subtrees built in parallel
    ThreadPool one(1), three(3);
    const Bvh a = build_bvh(mesh, {}, one);
    const Bvh b = build_bvh(mesh, {}, three);
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    EXPECT_EQ(a.prim_ids, b.prim_ids);
    EXPECT_EQ(0, std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(BvhNode)));
    std::size_t total = 0;
    for (const auto& n : b.nodes) {
        total += n.count;
    }
    EXPECT_EQ(total, mesh.triangle_count());
}

TEST(Bvh, DegenerateInputsStillBuild) {
    // 1000 copies of one triangle: centroids coincide, so the builder splits by index.
    TriangleMesh mesh;
    mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.faces.assign(1000, Face{0, 1, 2});
    ThreadPool pool(1);
    const Bvh bvh = build_bvh(mesh, {}, pool);
    std::size_t total = 0;
    for (const auto& n : bvh.nodes) {
        total += n.count;
    }
    EXPECT_EQ(total, 1000u);
    EXPECT_LE(bvh.depth, 120);
}

TEST(KdTree, FollowsTheReportRules) {
    const TriangleMesh mesh = test::make_icosphere(5, 5.0f);  // 20480 triangles
    const KdTree tree = build_kdtree(mesh, KdTreeBuildConfig::report());
    EXPECT_LE(tree.depth, 25);
    std::vector<int> seen(mesh.triangle_count(), 0);
    // Walk the tree tracking depth and the cyclic axis.
    struct Item {
        std::uint32_t node;
        int depth;
    };
    std::vector<Item> stack{{0, 1}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const KdNode& n = tree.nodes[it.node];
        if (n.is_leaf()) {
            EXPECT_TRUE(n.count() <= 30 || it.depth >= 25) << "leaf of " << n.count();
            for (std::uint32_t k = n.first(); k < n.first() + n.count(); ++k) {
                seen[tree.prim_ids[k]] = 1;
            }
        } else {
            EXPECT_EQ(n.axis(), static_cast<std::uint32_t>((it.depth - 1) % 3))
                << "axes cycle x, y, z";
            stack.push_back({it.node + 1, it.depth + 1});
            stack.push_back({n.right(), it.depth + 1});
        }
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }))
        << "every face reaches a leaf";
}

TEST(KdTree, SahTreeHoldsEveryFaceAndRespectsItsDepth) {
    const TriangleMesh mesh = test::make_icosphere(5, 5.0f);
    const KdTree tree = build_kdtree(mesh);
    EXPECT_LE(tree.depth, 8 + 19);  // 8 + 1.3 log2(20480)
    std::vector<int> seen(mesh.triangle_count(), 0);
    for (const auto& n : tree.nodes) {
        if (n.is_leaf()) {
            for (std::uint32_t k = n.first(); k < n.first() + n.count(); ++k) {
                seen[tree.prim_ids[k]] = 1;
            }
        }
    }
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; }));
}

TEST(KdTree, RejectsImpossibleSettings) {
    const TriangleMesh mesh = test::make_icosphere(1, 1.0f);
    KdTreeBuildConfig cfg;
    cfg.max_leaf_size = 0;
    EXPECT_THROW((void)build_kdtree(mesh, cfg), ConfigError);
    cfg.max_leaf_size = 2;
    cfg.max_depth = 100;
    EXPECT_THROW((void)build_kdtree(mesh, cfg), ConfigError);
}

/// A grid with a NaN vertex and an infinite one, and which faces touch neither.
struct PoisonedGrid {
    TriangleMesh mesh = test::make_grid(30);
    std::vector<bool> finite;
    PoisonedGrid() {
        mesh.vertices[40].x = std::numeric_limits<float>::quiet_NaN();
        mesh.vertices[300].z = std::numeric_limits<float>::infinity();
        for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
            const Face& face = mesh.faces[f];
            finite.push_back(std::none_of(face.begin(), face.end(),
                                          [](std::uint32_t v) { return v == 40u || v == 300u; }));
        }
    }
    /// Every finite face exactly once in `prim_ids`, no other.
    void expect_exactly_the_finite_faces(const std::vector<std::uint32_t>& prim_ids) const {
        std::vector<int> seen(mesh.triangle_count(), 0);
        for (const auto f : prim_ids) {
            ++seen[f];
        }
        std::size_t left_out = 0;
        for (std::size_t f = 0; f < seen.size(); ++f) {
            EXPECT_EQ(seen[f] > 0, finite[f]) << "face " << f;
            left_out += finite[f] ? 0 : 1;
        }
        EXPECT_GE(left_out, 6u);
    }
};

TEST(Bvh, FacesWithNonFiniteVerticesAreLeftOut) {
    const PoisonedGrid grid;
    ThreadPool pool(2);
    const Bvh bvh = build_bvh(grid.mesh, {}, pool);
    grid.expect_exactly_the_finite_faces(bvh.prim_ids);
    for (const BvhNode& n : bvh.nodes) {
        for (std::size_t a = 0; a < 3; ++a) {
            EXPECT_TRUE(std::isfinite(n.lo[a]) && std::isfinite(n.hi[a]));
        }
    }
}

TEST(KdTree, FacesWithNonFiniteVerticesAreLeftOut) {
    const PoisonedGrid grid;
    for (const KdSplitRule rule : {KdSplitRule::sah, KdSplitRule::report}) {
        KdTreeBuildConfig config;
        config.rule = rule;
        const KdTree tree = build_kdtree(grid.mesh, config);
        std::vector<std::uint32_t> ids(tree.prim_ids.begin(), tree.prim_ids.end());
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
        grid.expect_exactly_the_finite_faces(ids);
        for (std::size_t a = 0; a < 3; ++a) {
            EXPECT_TRUE(std::isfinite(tree.bounds.lo[a]) && std::isfinite(tree.bounds.hi[a]));
        }
    }
}

}  // namespace
}  // namespace beamtrace
