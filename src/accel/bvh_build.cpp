#include <algorithm>
#include <array>
#include <limits>

#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr int kMaxDepth = 120;  // the traversal stack holds 128 entries
constexpr int kMaxBins = 32;

/// Per-face build data, partitioned in place (sequential access, no indirection).
struct PrimInfo {
    Aabb box;
    Vec3f centroid;
    std::uint32_t id;
};

/// Plain bin data: only the bins in use are initialised.
struct Bin {
    Aabb box, cbox;
    std::uint32_t count;
};

/// A range of prim_ids with its bounds and centroid bounds.
struct Range {
    std::uint32_t begin = 0, end = 0;
    Aabb box, cbox;
    int depth = 1;
};

struct Split {
    std::uint32_t mid = 0;  ///< == begin: make a leaf
    Range left, right;
};

/// Binned SAH (Wald 2007). Child bounds come from the bins, so no pass re-reads the prims.
class SplitFinder {
  public:
    SplitFinder(std::vector<PrimInfo>& prims, const BvhBuildConfig& config)
        : prims_(prims), config_(config), bins_(std::clamp(config.bin_count, 2, kMaxBins)) {}

    [[nodiscard]] Split find(const Range& r) const {
        Split s;
        s.mid = r.begin;
        const std::uint32_t count = r.end - r.begin;
        if (count <= 1) {
            return s;
        }
        const auto max_leaf = static_cast<std::uint32_t>(std::max(1, config_.max_leaf_size));
        const bool must_split = count > max_leaf;
        if (r.depth >= kMaxDepth) {
            return s;
        }
        float best_cost = std::numeric_limits<float>::infinity();
        int best_axis = -1, best_bin = 0;
        // Deliberately uninitialised: only the first bins_ entries of each axis are set and used.
        Bin bins[3][kMaxBins];
        const Vec3f cext = r.cbox.extent();
        for (int axis = 0; axis < 3; ++axis) {
            const auto a = static_cast<std::size_t>(axis);
            if (!(cext[a] > 0.0f)) {
                continue;
            }
            Bin* b = bins[a];
            for (int k = 0; k < bins_; ++k) {
                b[k].box = Aabb{};
                b[k].cbox = Aabb{};
                b[k].count = 0;
            }
            const float scale = static_cast<float>(bins_) / cext[a];
            for (std::uint32_t i = r.begin; i < r.end; ++i) {
                const PrimInfo& p = prims_[i];
                Bin& bin = b[bin_of(p.centroid[a], r.cbox.lo[a], scale)];
                bin.box.extend(p.box);
                bin.cbox.extend(p.centroid);
                ++bin.count;
            }
            std::array<float, kMaxBins> right_cost{};
            Aabb acc;
            std::uint32_t n = 0;
            for (int k = bins_ - 1; k > 0; --k) {
                acc.extend(b[k].box);
                n += b[k].count;
                right_cost[static_cast<std::size_t>(k)] = acc.half_area() * static_cast<float>(n);
            }
            acc = Aabb{};
            n = 0;
            for (int k = 0; k < bins_ - 1; ++k) {
                acc.extend(b[k].box);
                n += b[k].count;
                const float cost = acc.half_area() * static_cast<float>(n) +
                                   right_cost[static_cast<std::size_t>(k) + 1];
                if (n > 0 && n < count && cost < best_cost) {
                    best_cost = cost;
                    best_axis = axis;
                    best_bin = k;
                }
            }
        }
        if (best_axis < 0) {
            // All centroids coincide: split by index if the leaf would be too big.
            return must_split ? split_by_index(r) : s;
        }
        const float area = r.box.half_area();
        const float leaf_cost = config_.intersection_cost * static_cast<float>(count);
        const float split_cost = config_.traversal_cost +
                                 config_.intersection_cost *
                                     (area > 0.0f ? best_cost / area : static_cast<float>(count));
        if (!must_split && split_cost >= leaf_cost) {
            return s;
        }
        const auto a = static_cast<std::size_t>(best_axis);
        const float scale = static_cast<float>(bins_) / cext[a];
        const float lo = r.cbox.lo[a];
        auto* first = prims_.data() + r.begin;
        auto* mid = std::partition(first, prims_.data() + r.end, [&](const PrimInfo& p) {
            return bin_of(p.centroid[a], lo, scale) <= best_bin;
        });
        s.mid = static_cast<std::uint32_t>(mid - prims_.data());
        s.left = {r.begin, s.mid, {}, {}, r.depth + 1};
        s.right = {s.mid, r.end, {}, {}, r.depth + 1};
        for (int k = 0; k < bins_; ++k) {
            const Bin& bin = bins[a][k];
            Range& side = k <= best_bin ? s.left : s.right;
            side.box.extend(bin.box);
            side.cbox.extend(bin.cbox);
        }
        return s;
    }

    [[nodiscard]] Range bounds_of(std::uint32_t begin, std::uint32_t end, int depth) const {
        Range r{begin, end, {}, {}, depth};
        for (std::uint32_t i = begin; i < end; ++i) {
            r.box.extend(prims_[i].box);
            r.cbox.extend(prims_[i].centroid);
        }
        return r;
    }

  private:
    [[nodiscard]] Split split_by_index(const Range& r) const {
        Split s;
        s.mid = r.begin + (r.end - r.begin) / 2;
        s.left = bounds_of(r.begin, s.mid, r.depth + 1);
        s.right = bounds_of(s.mid, r.end, r.depth + 1);
        return s;
    }

    [[nodiscard]] int bin_of(float c, float lo, float scale) const {
        return std::clamp(static_cast<int>((c - lo) * scale), 0, bins_ - 1);
    }

    std::vector<PrimInfo>& prims_;
    const BvhBuildConfig& config_;
    int bins_;
};

void set_bounds(BvhNode& n, const Aabb& box) {
    for (std::size_t a = 0; a < 3; ++a) {
        n.lo[a] = box.lo[a];
        n.hi[a] = box.hi[a];
    }
}

/// Builds the subtree of `root` into `nodes[at]`; children are appended as adjacent pairs.
/// `defer`, when set, receives ranges at `defer_depth` instead of building them (they are built
/// later, in parallel, and spliced in).
void build_subtree(const SplitFinder& finder, const Range& root, std::vector<BvhNode>& nodes,
                   std::uint32_t at, int& max_depth, int defer_depth,
                   std::vector<std::pair<std::uint32_t, Range>>* defer) {
    struct Item {
        std::uint32_t node;
        Range range;
    };
    std::vector<Item> stack{{at, root}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        max_depth = std::max(max_depth, it.range.depth);
        if (defer != nullptr && it.range.depth >= defer_depth) {
            defer->emplace_back(it.node, it.range);
            continue;
        }
        BvhNode& node = nodes[it.node];
        set_bounds(node, it.range.box);
        const Split s = finder.find(it.range);
        if (s.mid == it.range.begin || s.mid == it.range.end) {
            nodes[it.node].index = it.range.begin;
            nodes[it.node].count = it.range.end - it.range.begin;
            continue;
        }
        const auto left = static_cast<std::uint32_t>(nodes.size());
        nodes[it.node].index = left;
        nodes[it.node].count = 0;
        nodes.emplace_back();
        nodes.emplace_back();
        stack.push_back({left + 1, s.right});
        stack.push_back({left, s.left});
    }
}

}  // namespace

Bvh build_bvh(const TriangleMesh& mesh, const BvhBuildConfig& config, ThreadPool& pool) {
    Bvh bvh;
    const std::size_t n = mesh.triangle_count();
    if (n == 0) {
        return bvh;
    }
    if (n >= std::numeric_limits<std::uint32_t>::max()) {
        throw ConfigError("BVH: too many triangles (" + std::to_string(n) + ")");
    }
    std::vector<PrimInfo> prims(n);
    pool.parallel_for(n, 1 << 14, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
            prims[i].box = mesh.triangle_bounds(i);
            prims[i].centroid = prims[i].box.center();
            prims[i].id = static_cast<std::uint32_t>(i);
        }
    });
    const SplitFinder finder(prims, config);
    const Range root = finder.bounds_of(0, static_cast<std::uint32_t>(n), 1);
    bvh.nodes.reserve(2 * n / static_cast<std::size_t>(std::max(1, config.max_leaf_size / 2)) + 1);
    bvh.nodes.emplace_back();

    // The top levels serially, then the subtrees below in parallel (disjoint prim ranges), each
    // into its own node array, spliced in a fixed order: the result never depends on threads.
    const int defer_depth = n > 100000 ? 4 : kMaxDepth + 1;
    std::vector<std::pair<std::uint32_t, Range>> deferred;
    build_subtree(finder, root, bvh.nodes, 0, bvh.depth, defer_depth, &deferred);
    std::vector<std::vector<BvhNode>> parts(deferred.size());
    std::vector<int> depths(deferred.size(), 0);
    pool.parallel_for(deferred.size(), 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            parts[k].emplace_back();
            build_subtree(finder, deferred[k].second, parts[k], 0, depths[k], 0, nullptr);
        }
    });
    for (std::size_t k = 0; k < deferred.size(); ++k) {
        bvh.depth = std::max(bvh.depth, depths[k]);
        // Local node 0 goes into the placeholder; local nodes 1.. go to the end.
        const auto base = static_cast<std::uint32_t>(bvh.nodes.size()) - 1;
        auto& local = parts[k];
        for (auto& node : local) {
            if (!node.is_leaf()) {
                node.index += base;
            }
        }
        bvh.nodes[deferred[k].first] = local[0];
        bvh.nodes.insert(bvh.nodes.end(), local.begin() + 1, local.end());
    }
    bvh.prim_ids.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        bvh.prim_ids[i] = prims[i].id;
    }
    return bvh;
}

}  // namespace beamtrace
