#include <algorithm>
#include <array>
#include <cmath>
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

struct Bin {
    Aabb box;
    std::uint32_t count;
};

/// Bins of the three axes; only the first `n` of each are used.
struct BinSet {
    Bin bins[3][kMaxBins];
    void reset(int n) {
        for (auto& axis : bins) {
            for (int k = 0; k < n; ++k) {
                axis[k].box = Aabb{};
                axis[k].count = 0;
            }
        }
    }
    void merge(const BinSet& o, int n) {
        for (std::size_t a = 0; a < 3; ++a) {
            for (int k = 0; k < n; ++k) {
                bins[a][k].box.extend(o.bins[a][k].box);
                bins[a][k].count += o.bins[a][k].count;
            }
        }
    }
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

/// Binned SAH (Wald 2007). Child bounds come from the bins and the partition pass, so no extra
/// pass reads the faces.
class SplitFinder {
  public:
    /// `pool`, when not null, bins large nodes in parallel (only from a thread outside the pool).
    SplitFinder(std::vector<PrimInfo>& prims, const BvhBuildConfig& config, ThreadPool* pool)
        : prims_(prims),
          config_(config),
          bins_(std::clamp(config.bin_count, 2, kMaxBins)),
          pool_(pool) {}

    [[nodiscard]] Split find(const Range& r) const {
        Split s;
        s.mid = r.begin;
        const std::uint32_t count = r.end - r.begin;
        if (count <= static_cast<std::uint32_t>(std::max(1, config_.min_leaf_size)) ||
            r.depth >= kMaxDepth) {
            return s;
        }
        const bool must_split =
            count > static_cast<std::uint32_t>(std::max(1, config_.max_leaf_size));
        // One pass over the faces fills the bins of all three axes (in parallel chunks for the
        // large nodes at the top; merging boxes and counts is exact, so the order is irrelevant).
        BinSet bins;
        const Vec3f lo = r.cbox.lo;
        const Vec3f cext = r.cbox.extent();
        Vec3f scale;
        for (std::size_t a = 0; a < 3; ++a) {
            scale[a] = cext[a] > 0.0f ? static_cast<float>(bins_) / cext[a] : 0.0f;
        }
        const auto fill = [&](BinSet& set, std::uint32_t b, std::uint32_t e) {
            set.reset(bins_);
            for (std::uint32_t i = b; i < e; ++i) {
                const PrimInfo& p = prims_[i];
                for (std::size_t a = 0; a < 3; ++a) {
                    Bin& bin = set.bins[a][bin_of(p.centroid[a], lo[a], scale[a])];
                    bin.box.extend(p.box);
                    ++bin.count;
                }
            }
        };
        constexpr std::uint32_t kParallelBinning = 1u << 16;
        if (pool_ != nullptr && pool_->size() > 1 && count >= kParallelBinning) {
            const std::size_t chunks = 4 * pool_->size();
            const std::uint32_t step = (count + static_cast<std::uint32_t>(chunks) - 1) /
                                       static_cast<std::uint32_t>(chunks);
            std::vector<BinSet> partial(chunks);
            pool_->parallel_for(chunks, 1, [&](std::size_t cb, std::size_t ce) {
                for (std::size_t c = cb; c < ce; ++c) {
                    const std::uint32_t b = r.begin + static_cast<std::uint32_t>(c) * step;
                    fill(partial[c], std::min(b, r.end), std::min(b + step, r.end));
                }
            });
            bins.reset(bins_);
            for (const auto& part : partial) {
                bins.merge(part, bins_);
            }
        } else {
            fill(bins, r.begin, r.end);
        }
        float best_cost = std::numeric_limits<float>::infinity();
        int best_axis = -1, best_bin = 0;
        for (std::size_t a = 0; a < 3; ++a) {
            if (!(cext[a] > 0.0f)) {
                continue;
            }
            const Bin* b = bins.bins[a];
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
                    best_axis = static_cast<int>(a);
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
        // Partition in place, collecting the children's centroid bounds on the way.
        const auto a = static_cast<std::size_t>(best_axis);
        s.left = {r.begin, 0, {}, {}, r.depth + 1};
        s.right = {0, r.end, {}, {}, r.depth + 1};
        std::uint32_t i = r.begin, j = r.end;
        while (i < j) {
            if (bin_of(prims_[i].centroid[a], lo[a], scale[a]) <= best_bin) {
                s.left.cbox.extend(prims_[i].centroid);
                ++i;
            } else {
                --j;
                std::swap(prims_[i], prims_[j]);
                s.right.cbox.extend(prims_[j].centroid);
            }
        }
        s.mid = i;
        s.left.end = s.right.begin = s.mid;
        for (int k = 0; k < bins_; ++k) {
            (k <= best_bin ? s.left : s.right).box.extend(bins.bins[a][k].box);
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

    /// The bin of centroid coordinate `c`, clamped; a NaN position goes to bin 0 rather than
    /// being cast to int (undefined behaviour).
    [[nodiscard]] int bin_of(float c, float lo, float scale) const {
        const float t = (c - lo) * scale;
        if (!(t > 0.0f)) {
            return 0;
        }
        return t < static_cast<float>(bins_) ? static_cast<int>(t) : bins_ - 1;
    }

    std::vector<PrimInfo>& prims_;
    const BvhBuildConfig& config_;
    int bins_;
    ThreadPool* pool_;
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

[[nodiscard]] bool finite_face(const TriangleMesh& mesh, std::size_t f) {
    for (const std::uint32_t v : mesh.faces[f]) {
        const Vec3f& p = mesh.vertices[v];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) {
            return false;
        }
    }
    return true;
}

/// Builds over prepared primitives (box, centroid, id), which it reorders. Primitives whose box
/// is not finite (a NaN or infinite vertex: no ray can hit them) are left out.
Bvh build_over(std::vector<PrimInfo>& prims, const BvhBuildConfig& config, ThreadPool& pool) {
    std::erase_if(prims, [](const PrimInfo& p) {
        return !(std::isfinite(p.box.lo.x) && std::isfinite(p.box.lo.y) &&
                 std::isfinite(p.box.lo.z) && std::isfinite(p.box.hi.x) &&
                 std::isfinite(p.box.hi.y) && std::isfinite(p.box.hi.z));
    });
    Bvh bvh;
    const std::size_t n = prims.size();
    if (n == 0) {
        return bvh;
    }
    const SplitFinder top_finder(prims, config, &pool);
    const SplitFinder finder(prims, config, nullptr);
    const Range root = top_finder.bounds_of(0, static_cast<std::uint32_t>(n), 1);
    bvh.nodes.reserve(2 * n / static_cast<std::size_t>(std::max(1, config.min_leaf_size)) + 1);
    bvh.nodes.emplace_back();

    // The top levels serially, then the subtrees below in parallel (disjoint prim ranges), each
    // into its own node array, spliced in a fixed order: the result never depends on threads.
    const int defer_depth = n > 100000 ? 4 : kMaxDepth + 1;
    std::vector<std::pair<std::uint32_t, Range>> deferred;
    build_subtree(top_finder, root, bvh.nodes, 0, bvh.depth, defer_depth, &deferred);
    std::vector<std::vector<BvhNode>> parts(deferred.size());
    std::vector<int> depths(deferred.size(), 0);
    pool.parallel_for(deferred.size(), 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
            const std::uint32_t faces = deferred[k].second.end - deferred[k].second.begin;
            parts[k].reserve(
                2 * faces / static_cast<std::uint32_t>(std::max(1, config.min_leaf_size)) + 1);
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

}  // namespace

Bvh build_bvh(const TriangleMesh& mesh, const BvhBuildConfig& config, ThreadPool& pool) {
    const std::size_t n = mesh.triangle_count();
    if (n >= std::numeric_limits<std::uint32_t>::max()) {
        throw ConfigError("BVH: too many triangles (" + std::to_string(n) + ")");
    }
    std::vector<PrimInfo> prims(n);
    pool.parallel_for(n, 1 << 14, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
            // min/max drop a NaN coordinate from the bounds: a face with a non-finite vertex
            // gets an empty (infinite) box instead, so that build_over leaves it out.
            prims[i].box = finite_face(mesh, i) ? mesh.triangle_bounds(i) : Aabb{};
            prims[i].centroid = prims[i].box.center();
            prims[i].id = static_cast<std::uint32_t>(i);
        }
    });
    return build_over(prims, config, pool);
}

Bvh build_bvh(std::span<const Aabb> boxes, const BvhBuildConfig& config, ThreadPool& pool) {
    const std::size_t n = boxes.size();
    if (n >= std::numeric_limits<std::uint32_t>::max()) {
        throw ConfigError("BVH: too many primitives (" + std::to_string(n) + ")");
    }
    std::vector<PrimInfo> prims(n);
    for (std::size_t i = 0; i < n; ++i) {
        prims[i].box = boxes[i];
        prims[i].centroid = boxes[i].center();
        prims[i].id = static_cast<std::uint32_t>(i);
    }
    return build_over(prims, config, pool);
}

}  // namespace beamtrace
