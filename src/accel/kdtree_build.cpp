#include <algorithm>
#include <array>
#include <limits>

#include "beamtrace/accel/kdtree.hpp"
#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

class KdBuilder {
  public:
    KdBuilder(const TriangleMesh& mesh, const KdTreeBuildConfig& config, KdTree& tree)
        : mesh_(mesh), config_(config), tree_(tree) {
        boxes_.resize(mesh.triangle_count());
        for (std::size_t i = 0; i < boxes_.size(); ++i) {
            boxes_[i] = mesh.triangle_bounds(i);
        }
    }

    // `faces` is consumed (moved into the children) to bound peak memory.
    void build(std::uint32_t node_index, std::vector<std::uint32_t> faces, const Aabb& bounds,
               int depth, int axis) {
        tree_.depth = std::max(tree_.depth, depth);
        const auto n = faces.size();
        float split = 0.0f;
        if (n <= static_cast<std::size_t>(config_.max_leaf_size) || depth >= config_.max_depth ||
            !choose_split(faces, bounds, axis, split)) {
            make_leaf(node_index, faces);
            return;
        }
        const auto a = static_cast<std::size_t>(axis);
        std::vector<std::uint32_t> left, right;
        for (auto f : faces) {
            if (boxes_[f].lo[a] <= split) {
                left.push_back(f);
            }
            if (boxes_[f].hi[a] > split) {
                right.push_back(f);
            }
        }
        std::vector<std::uint32_t>().swap(faces);
        Aabb left_bounds = bounds, right_bounds = bounds;
        left_bounds.hi[a] = split;
        right_bounds.lo[a] = split;
        const int next_axis = (axis + 1) % 3;

        tree_.nodes[node_index].axis = static_cast<std::uint32_t>(axis);
        tree_.nodes[node_index].split = split;
        const auto left_index = static_cast<std::uint32_t>(tree_.nodes.size());
        tree_.nodes.emplace_back();
        build(left_index, std::move(left), left_bounds, depth + 1, next_axis);
        const auto right_index = static_cast<std::uint32_t>(tree_.nodes.size());
        tree_.nodes.emplace_back();
        tree_.nodes[node_index].index = right_index;
        build(right_index, std::move(right), right_bounds, depth + 1, next_axis);
    }

  private:
    void make_leaf(std::uint32_t node_index, const std::vector<std::uint32_t>& faces) {
        KdNode& node = tree_.nodes[node_index];
        node.axis = 3;
        node.index = static_cast<std::uint32_t>(tree_.prim_ids.size());
        node.count = static_cast<std::uint32_t>(faces.size());
        tree_.prim_ids.insert(tree_.prim_ids.end(), faces.begin(), faces.end());
    }

    /// The report's findKDSplitPlane with exact counts: candidates are the first, median and last
    /// vertex coordinate along `axis`. Returns false when no candidate separates anything (or,
    /// with sah_termination, when a leaf is cheaper).
    bool choose_split(const std::vector<std::uint32_t>& faces, const Aabb& bounds, int axis,
                      float& split) {
        const auto a = static_cast<std::size_t>(axis);
        coords_.clear();
        for (auto f : faces) {
            for (auto v : mesh_.faces[f]) {
                coords_.push_back(mesh_.vertices[v][a]);
            }
        }
        const std::size_t median_rank = (coords_.size() + 1) / 2 - 1;  // Matlab ceil(0.5*n)
        std::nth_element(coords_.begin(),
                         coords_.begin() + static_cast<std::ptrdiff_t>(median_rank), coords_.end());
        const float median = coords_[median_rank];
        const auto [mn, mx] = std::minmax_element(coords_.begin(), coords_.end());
        const std::array<float, 3> candidates{*mn, *mx, median};

        const float n = static_cast<float>(faces.size());
        const float area = bounds.half_area();
        float best_cost = std::numeric_limits<float>::infinity();
        bool found = false;
        for (float c : candidates) {
            const float pos = std::clamp(c, bounds.lo[a], bounds.hi[a]);
            std::size_t n_left = 0, n_right = 0;
            for (auto f : faces) {
                n_left += boxes_[f].lo[a] <= pos ? 1 : 0;
                n_right += boxes_[f].hi[a] > pos ? 1 : 0;
            }
            if (n_left == faces.size() && n_right == faces.size()) {
                continue;  // separates nothing
            }
            if (n_left == 0 || n_right == 0) {
                // Only worth it when it cuts off empty space.
                if (pos <= bounds.lo[a] || pos >= bounds.hi[a]) {
                    continue;
                }
            }
            Aabb lb = bounds, rb = bounds;
            lb.hi[a] = pos;
            rb.lo[a] = pos;
            const float weighted = lb.half_area() * static_cast<float>(n_left) +
                                   rb.half_area() * static_cast<float>(n_right);
            const float cost =
                config_.traversal_cost +
                config_.intersection_cost *
                    (area > 0.0f ? weighted / area : 0.5f * static_cast<float>(n_left + n_right));
            if (cost < best_cost) {
                best_cost = cost;
                split = pos;
                found = true;
            }
        }
        if (found && config_.sah_termination && best_cost >= config_.intersection_cost * n) {
            return false;
        }
        return found;
    }

    const TriangleMesh& mesh_;
    const KdTreeBuildConfig& config_;
    KdTree& tree_;
    std::vector<Aabb> boxes_;
    std::vector<float> coords_;
};

}  // namespace

KdTree build_kdtree(const TriangleMesh& mesh, const KdTreeBuildConfig& config) {
    if (config.max_depth < 1 || config.max_depth > 60 || config.max_leaf_size < 1) {
        throw ConfigError("k-d tree: max_depth must be in [1, 60] and max_leaf_size at least 1");
    }
    KdTree tree;
    tree.bounds = mesh.bounds();
    tree.nodes.emplace_back();
    std::vector<std::uint32_t> faces(mesh.triangle_count());
    for (std::size_t i = 0; i < faces.size(); ++i) {
        faces[i] = static_cast<std::uint32_t>(i);
    }
    if (faces.empty()) {
        return tree;
    }
    KdBuilder builder(mesh, config, tree);
    builder.build(0, std::move(faces), tree.bounds, 1, 0);
    return tree;
}

}  // namespace beamtrace
