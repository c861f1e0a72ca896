#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "beamtrace/accel/kdtree.hpp"
#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr int kMaxDepthLimit = 60;  // the traversal stack holds 64 entries
constexpr int kMaxBins = 64;

struct Candidate {
    float pos = 0.0f;
    float cost = std::numeric_limits<float>::infinity();
    int axis = -1;
};

class KdBuilder {
  public:
    KdBuilder(const TriangleMesh& mesh, const KdTreeBuildConfig& config, int max_depth,
              KdTree& tree)
        : mesh_(mesh), config_(config), max_depth_(max_depth), tree_(tree) {
        boxes_.resize(mesh.triangle_count());
        for (std::size_t i = 0; i < boxes_.size(); ++i) {
            boxes_[i] = mesh.triangle_bounds(i);
        }
    }

    // `faces` is consumed (moved into the children) to bound peak memory.
    void build(std::uint32_t node_index, std::vector<std::uint32_t> faces, const Aabb& bounds,
               int depth, int axis) {
        tree_.depth = std::max(tree_.depth, depth);
        if (faces.size() <= static_cast<std::size_t>(config_.max_leaf_size) ||
            depth >= max_depth_) {
            make_leaf(node_index, faces);
            return;
        }
        const Candidate c = config_.rule == KdSplitRule::report ? report_split(faces, bounds, axis)
                                                                : sah_split(faces, bounds);
        if (c.axis < 0) {
            make_leaf(node_index, faces);
            return;
        }
        const auto a = static_cast<std::size_t>(c.axis);
        std::vector<std::uint32_t> left, right;
        for (auto f : faces) {
            if (boxes_[f].lo[a] <= c.pos) {
                left.push_back(f);
            }
            if (boxes_[f].hi[a] > c.pos) {
                right.push_back(f);
            }
        }
        std::vector<std::uint32_t>().swap(faces);
        Aabb left_bounds = bounds, right_bounds = bounds;
        left_bounds.hi[a] = c.pos;
        right_bounds.lo[a] = c.pos;
        const int next_axis = (c.axis + 1) % 3;

        tree_.nodes[node_index] = KdNode::inner(c.axis, c.pos);
        const auto left_index = static_cast<std::uint32_t>(tree_.nodes.size());
        tree_.nodes.emplace_back();
        build(left_index, std::move(left), left_bounds, depth + 1, next_axis);
        const auto right_index = static_cast<std::uint32_t>(tree_.nodes.size());
        tree_.nodes.emplace_back();
        tree_.nodes[node_index].set_right(right_index);
        build(right_index, std::move(right), right_bounds, depth + 1, next_axis);
    }

  private:
    void make_leaf(std::uint32_t node_index, const std::vector<std::uint32_t>& faces) {
        if (faces.size() >= (1u << 30) || tree_.prim_ids.size() + faces.size() >= (1ull << 32)) {
            throw ConfigError("k-d tree: too many face references (degenerate input?)");
        }
        tree_.nodes[node_index] = KdNode::leaf(static_cast<std::uint32_t>(tree_.prim_ids.size()),
                                               static_cast<std::uint32_t>(faces.size()));
        tree_.prim_ids.insert(tree_.prim_ids.end(), faces.begin(), faces.end());
    }

    /// SAH cost of splitting `bounds` at `pos` on axis `a` with the given counts.
    [[nodiscard]] float split_cost(const Aabb& bounds, std::size_t a, float pos, std::size_t n_left,
                                   std::size_t n_right, float empty_bonus) const {
        Aabb lb = bounds, rb = bounds;
        lb.hi[a] = pos;
        rb.lo[a] = pos;
        const float area = bounds.half_area();
        const float weighted = lb.half_area() * static_cast<float>(n_left) +
                               rb.half_area() * static_cast<float>(n_right);
        const float bonus = (n_left == 0 || n_right == 0) ? 1.0f - empty_bonus : 1.0f;
        return config_.traversal_cost +
               config_.intersection_cost * bonus *
                   (area > 0.0f ? weighted / area : 0.5f * static_cast<float>(n_left + n_right));
    }

    /// The report's findKDSplitPlane with exact counts: candidates are the first, median and last
    /// vertex coordinate along the cyclic axis. No candidate when none separates anything.
    Candidate report_split(const std::vector<std::uint32_t>& faces, const Aabb& bounds, int axis) {
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
        Candidate best;
        for (float c : {*mn, *mx, median}) {
            const float pos = std::clamp(c, bounds.lo[a], bounds.hi[a]);
            std::size_t n_left = 0, n_right = 0;
            for (auto f : faces) {
                n_left += boxes_[f].lo[a] <= pos ? 1 : 0;
                n_right += boxes_[f].hi[a] > pos ? 1 : 0;
            }
            if (n_left == faces.size() && n_right == faces.size()) {
                continue;  // separates nothing
            }
            if ((n_left == 0 || n_right == 0) && (pos <= bounds.lo[a] || pos >= bounds.hi[a])) {
                continue;  // an empty side of zero width cuts nothing off
            }
            const float cost = split_cost(bounds, a, pos, n_left, n_right, 0.0f);
            if (cost < best.cost) {
                best = {pos, cost, axis};
            }
        }
        return best;
    }

    /// Binned SAH over all three axes; no candidate when a leaf is cheaper.
    Candidate sah_split(const std::vector<std::uint32_t>& faces, const Aabb& bounds) const {
        const int bins = std::clamp(config_.bin_count, 2, kMaxBins);
        Candidate best;
        const Vec3f ext = bounds.extent();
        for (std::size_t a = 0; a < 3; ++a) {
            if (!(ext[a] > 0.0f)) {
                continue;
            }
            std::array<std::uint32_t, kMaxBins> starts{}, ends{};
            const float scale = static_cast<float>(bins) / ext[a];
            const auto bin_of = [&](float x) {  // NaN to bin 0, not cast to int (UB)
                const float t = (x - bounds.lo[a]) * scale;
                if (!(t > 0.0f)) {
                    return 0;
                }
                return t < static_cast<float>(bins) ? static_cast<int>(t) : bins - 1;
            };
            for (auto f : faces) {
                ++starts[static_cast<std::size_t>(bin_of(boxes_[f].lo[a]))];
                ++ends[static_cast<std::size_t>(bin_of(boxes_[f].hi[a]))];
            }
            // Plane k sits between bins k-1 and k: left = faces starting below it, right = faces
            // ending at or above it.
            std::size_t n_left = 0, n_right = faces.size();
            for (int k = 1; k < bins; ++k) {
                n_left += starts[static_cast<std::size_t>(k - 1)];
                n_right -= ends[static_cast<std::size_t>(k - 1)];
                const float pos = bounds.lo[a] + static_cast<float>(k) / scale;
                const float cost = split_cost(bounds, a, pos, n_left, n_right, config_.empty_bonus);
                if (cost < best.cost) {
                    best = {pos, cost, static_cast<int>(a)};
                }
            }
        }
        if (best.cost >= config_.intersection_cost * static_cast<float>(faces.size())) {
            return {};
        }
        return best;
    }

    const TriangleMesh& mesh_;
    const KdTreeBuildConfig& config_;
    int max_depth_;
    KdTree& tree_;
    std::vector<Aabb> boxes_;
    std::vector<float> coords_;
};

/// The faces whose bounds are finite: one with a NaN or infinite vertex (which no ray can hit)
/// is left out of the tree.
std::vector<std::uint32_t> finite_faces(const TriangleMesh& mesh) {
    std::vector<std::uint32_t> faces;
    faces.reserve(mesh.triangle_count());
    for (std::size_t i = 0; i < mesh.triangle_count(); ++i) {
        const Face& face = mesh.faces[i];
        if (std::all_of(face.begin(), face.end(), [&](std::uint32_t v) {
                const Vec3f& p = mesh.vertices[v];
                return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
            })) {
            faces.push_back(static_cast<std::uint32_t>(i));
        }
    }
    return faces;
}

}  // namespace

KdTree build_kdtree(const TriangleMesh& mesh, const KdTreeBuildConfig& config) {
    if (config.max_depth < 0 || config.max_depth > kMaxDepthLimit || config.max_leaf_size < 1) {
        throw ConfigError(
            "k-d tree: max_depth must be in [0, 60] (0 = automatic) and "
            "max_leaf_size at least 1");
    }
    KdTree tree;
    tree.bounds = mesh.bounds();
    tree.nodes.emplace_back();
    std::vector<std::uint32_t> faces = finite_faces(mesh);
    const Aabb& b = tree.bounds;
    const bool finite = std::isfinite(b.lo.x) && std::isfinite(b.lo.y) && std::isfinite(b.lo.z) &&
                        std::isfinite(b.hi.x) && std::isfinite(b.hi.y) && std::isfinite(b.hi.z);
    if (faces.size() < mesh.triangle_count() || (!finite && !faces.empty())) {
        // some left out (or a stray vertex): the bounds of the faces kept
        tree.bounds = Aabb{};
        for (const auto f : faces) {
            tree.bounds.extend(mesh.triangle_bounds(f));
        }
    }
    if (faces.empty()) {
        return tree;
    }
    int max_depth = config.max_depth;
    if (max_depth == 0) {
        max_depth = std::min(
            kMaxDepthLimit,
            8 + static_cast<int>(std::lround(1.3 * std::log2(static_cast<double>(faces.size())))));
    }
    KdBuilder builder(mesh, config, max_depth, tree);
    builder.build(0, std::move(faces), tree.bounds, 1, 0);
    return tree;
}

}  // namespace beamtrace
