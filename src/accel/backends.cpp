// The three backends: brute force (the oracle), the report's k-d tree and the binned-SAH BVH.
#include <cmath>
#include <string>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/accel/bvh.hpp"
#include "beamtrace/accel/kdtree.hpp"
#include "beamtrace/core/error.hpp"
#include "detail/queries.hpp"

namespace beamtrace {
namespace {

using detail::slab_entry;
using detail::TraceRay;

constexpr float kPad = 2.0f * 3.0f * std::numeric_limits<float>::epsilon();

struct BruteForceTraverser {
    std::uint32_t face_count = 0;
    template <class Visitor>
    void traverse(const TraceRay& /*ray*/, Visitor& vis) const {
        for (std::uint32_t f = 0; f < face_count; ++f) {
            if (vis.visit(f)) {
                return;
            }
        }
    }
};

struct BvhTraverser {
    Bvh bvh;

    template <class Visitor>
    void traverse(const TraceRay& r, Visitor& vis) const {
        if (bvh.nodes.empty()) {
            return;
        }
        struct Entry {
            std::uint32_t node;
            float tnear;
        };
        Entry stack[128];
        int sp = 0;
        const BvhNode* nodes = bvh.nodes.data();
        float tnear = 0.0f;
        if (!slab_entry(r, nodes[0].lo, nodes[0].hi, r.tmin, vis.limit(), tnear)) {
            return;
        }
        std::uint32_t index = 0;
        for (;;) {
            const BvhNode& node = nodes[index];
            if (node.is_leaf()) {
                for (std::uint32_t k = node.index; k < node.index + node.count; ++k) {
                    if (vis.visit(bvh.prim_ids[k])) {
                        return;
                    }
                }
            } else {
                const std::uint32_t li = node.index, ri = node.index + 1;
                const float limit = vis.limit();
                float tl = 0.0f, tr = 0.0f;
                const bool hl = slab_entry(r, nodes[li].lo, nodes[li].hi, r.tmin, limit, tl);
                const bool hr = slab_entry(r, nodes[ri].lo, nodes[ri].hi, r.tmin, limit, tr);
                if (hl && hr) {
                    if (tl <= tr) {
                        stack[sp++] = {ri, tr};
                        index = li;
                    } else {
                        stack[sp++] = {li, tl};
                        index = ri;
                    }
                    continue;
                }
                if (hl || hr) {
                    index = hl ? li : ri;
                    continue;
                }
            }
            // Pop the next node that may still hold a closer hit.
            for (;;) {
                if (sp == 0) {
                    return;
                }
                const Entry e = stack[--sp];
                if (e.tnear <= vis.limit()) {
                    index = e.node;
                    break;
                }
            }
        }
    }
};

struct KdTreeTraverser {
    KdTree tree;

    template <class Visitor>
    void traverse(const TraceRay& r, Visitor& vis) const {
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

BackendKind parse_backend_kind(std::string_view name) {
    if (name == "brute") {
        return BackendKind::brute;
    }
    if (name == "kdtree") {
        return BackendKind::kdtree;
    }
    if (name == "bvh") {
        return BackendKind::bvh;
    }
    throw ConfigError("unknown backend '" + std::string(name) +
                      "' (expected bvh, kdtree or brute)");
}

std::string_view to_string(BackendKind kind) {
    switch (kind) {
        case BackendKind::brute:
            return "brute";
        case BackendKind::kdtree:
            return "kdtree";
        case BackendKind::bvh:
            return "bvh";
    }
    return "?";
}

std::unique_ptr<Backend> make_backend(BackendKind kind, const TriangleMesh& mesh, ThreadPool& pool,
                                      const BackendConfig& config) {
    switch (kind) {
        case BackendKind::brute:
            return std::make_unique<detail::QueryBackend<BruteForceTraverser, BackendKind::brute>>(
                mesh, BruteForceTraverser{static_cast<std::uint32_t>(mesh.triangle_count())});
        case BackendKind::kdtree:
            return std::make_unique<detail::QueryBackend<KdTreeTraverser, BackendKind::kdtree>>(
                mesh, KdTreeTraverser{build_kdtree(mesh, config.kdtree)});
        case BackendKind::bvh:
            return std::make_unique<detail::QueryBackend<BvhTraverser, BackendKind::bvh>>(
                mesh, BvhTraverser{build_bvh(mesh, config.bvh, pool)});
    }
    throw ConfigError("unknown backend kind");
}

}  // namespace beamtrace
