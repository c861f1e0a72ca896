#include <algorithm>
#include <array>
#include <limits>

#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr int kMaxDepth = 120;  // the traversal stack holds 128 entries
constexpr int kMaxBins = 64;

struct PrimInfo {
    Aabb box;
    Vec3f centroid;
};

class BvhBuilder {
  public:
    BvhBuilder(const std::vector<PrimInfo>& prims, const BvhBuildConfig& config, Bvh& bvh)
        : prims_(prims), config_(config), bvh_(bvh) {
        bins_ = std::clamp(config.bin_count, 2, kMaxBins);
    }

    void build_node(std::uint32_t node_index, std::uint32_t begin, std::uint32_t end, int depth) {
        bvh_.depth = std::max(bvh_.depth, depth);
        Aabb box, cbox;
        for (std::uint32_t i = begin; i < end; ++i) {
            const PrimInfo& p = prims_[bvh_.prim_ids[i]];
            box.extend(p.box);
            cbox.extend(p.centroid);
        }
        set_bounds(node_index, box);
        const std::uint32_t count = end - begin;
        const std::uint32_t mid = choose_split(begin, end, box, cbox, depth);
        if (mid == begin || mid == end) {
            bvh_.nodes[node_index].index = begin;
            bvh_.nodes[node_index].count = count;
            return;
        }
        const auto left = static_cast<std::uint32_t>(bvh_.nodes.size());
        bvh_.nodes.emplace_back();
        build_node(left, begin, mid, depth + 1);
        const auto right = static_cast<std::uint32_t>(bvh_.nodes.size());
        bvh_.nodes.emplace_back();
        bvh_.nodes[node_index].index = right;
        bvh_.nodes[node_index].count = 0;
        build_node(right, mid, end, depth + 1);
    }

  private:
    void set_bounds(std::uint32_t node_index, const Aabb& box) {
        BvhNode& n = bvh_.nodes[node_index];
        for (std::size_t a = 0; a < 3; ++a) {
            n.lo[a] = box.lo[a];
            n.hi[a] = box.hi[a];
        }
    }

    /// Returns the partition point, or `begin` to make a leaf.
    std::uint32_t choose_split(std::uint32_t begin, std::uint32_t end, const Aabb& box,
                               const Aabb& cbox, int depth) {
        const std::uint32_t count = end - begin;
        const auto max_leaf = static_cast<std::uint32_t>(std::max(1, config_.max_leaf_size));
        if (count <= 1) {
            return begin;
        }
        const float leaf_cost = config_.intersection_cost * static_cast<float>(count);
        float best_cost = std::numeric_limits<float>::infinity();
        int best_axis = -1, best_bin = 0;
        const Vec3f cext = cbox.extent();
        for (int axis = 0; axis < 3; ++axis) {
            const auto a = static_cast<std::size_t>(axis);
            if (!(cext[a] > 0.0f)) {
                continue;
            }
            std::array<Aabb, kMaxBins> bin_box{};
            std::array<std::uint32_t, kMaxBins> bin_count{};
            const float scale = static_cast<float>(bins_) / cext[a];
            for (std::uint32_t i = begin; i < end; ++i) {
                const PrimInfo& p = prims_[bvh_.prim_ids[i]];
                const int b = bin_of(p.centroid[a], cbox.lo[a], scale);
                bin_box[static_cast<std::size_t>(b)].extend(p.box);
                ++bin_count[static_cast<std::size_t>(b)];
            }
            std::array<float, kMaxBins> right_cost{};
            Aabb acc;
            std::uint32_t n = 0;
            for (int b = bins_ - 1; b > 0; --b) {
                acc.extend(bin_box[static_cast<std::size_t>(b)]);
                n += bin_count[static_cast<std::size_t>(b)];
                right_cost[static_cast<std::size_t>(b)] = acc.half_area() * static_cast<float>(n);
            }
            acc = Aabb{};
            n = 0;
            for (int b = 0; b < bins_ - 1; ++b) {
                acc.extend(bin_box[static_cast<std::size_t>(b)]);
                n += bin_count[static_cast<std::size_t>(b)];
                const float cost = acc.half_area() * static_cast<float>(n) +
                                   right_cost[static_cast<std::size_t>(b) + 1];
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = axis;
                    best_bin = b;
                }
            }
        }
        const float area = box.half_area();
        const float split_cost = config_.traversal_cost +
                                 config_.intersection_cost *
                                     (area > 0.0f ? best_cost / area : static_cast<float>(count));
        const bool must_split = count > max_leaf || depth >= kMaxDepth;
        if (best_axis < 0) {
            // All centroids coincide: split by index if the leaf would be too big.
            return (must_split && depth < kMaxDepth) ? begin + count / 2 : begin;
        }
        if (!must_split && split_cost >= leaf_cost) {
            return begin;
        }
        if (depth >= kMaxDepth) {
            return begin;
        }
        const auto a = static_cast<std::size_t>(best_axis);
        const float scale = static_cast<float>(bins_) / cext[a];
        const float lo = cbox.lo[a];
        auto* first = bvh_.prim_ids.data() + begin;
        auto* last = bvh_.prim_ids.data() + end;
        auto* mid = std::partition(first, last, [&](std::uint32_t id) {
            return bin_of(prims_[id].centroid[a], lo, scale) <= best_bin;
        });
        auto m = static_cast<std::uint32_t>(mid - bvh_.prim_ids.data());
        if (m == begin || m == end) {
            m = begin + count / 2;
        }
        return m;
    }

    [[nodiscard]] int bin_of(float c, float lo, float scale) const {
        const int b = static_cast<int>((c - lo) * scale);
        return std::clamp(b, 0, bins_ - 1);
    }

    const std::vector<PrimInfo>& prims_;
    const BvhBuildConfig& config_;
    Bvh& bvh_;
    int bins_ = 16;
};

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
        }
    });
    bvh.prim_ids.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        bvh.prim_ids[i] = static_cast<std::uint32_t>(i);
    }
    bvh.nodes.reserve(2 * n / std::max(1, config.max_leaf_size / 2) + 1);
    bvh.nodes.emplace_back();
    BvhBuilder builder(prims, config, bvh);
    builder.build_node(0, 0, static_cast<std::uint32_t>(n), 1);
    return bvh;
}

}  // namespace beamtrace
