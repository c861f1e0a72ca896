// glTF 2.0: walks the default scene's node tree and triangulates its mesh primitives.
#include "beamtrace/scene/gltf_loader.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "scene/detail/gltf_document.hpp"
#include "text/text_scan.hpp"

namespace beamtrace {
namespace {

using detail::GltfDocument;
using nlohmann::json;

constexpr std::uint64_t kModeTriangles = 4;
constexpr std::uint64_t kModeTriangleStrip = 5;
constexpr std::uint64_t kModeTriangleFan = 6;

/// An affine map p' = A p + t stored as the top three rows of a 4x4 matrix (row-major).
struct Affine {
    std::array<std::array<double, 4>, 3> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

    [[nodiscard]] Vec3d apply(const Vec3d& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
};

/// a * b: applies b first.
[[nodiscard]] Affine compose(const Affine& a, const Affine& b) {
    Affine r;
    for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 4; ++j) {
            double v = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
            if (j == 3) {
                v += a.m[i][3];
            }
            r.m[i][j] = v;
        }
    }
    return r;
}

/// The node's local transform: `matrix` (column-major), else T * R * S.
[[nodiscard]] Affine local_transform(const GltfDocument& doc, const json& node,
                                     const std::string& where) {
    Affine t;
    if (const auto matrix = doc.optional_numbers(node, "matrix", 16, where)) {
        for (std::size_t r = 0; r < 3; ++r) {
            for (std::size_t c = 0; c < 4; ++c) {
                t.m[r][c] = (*matrix)[c * 4 + r];
            }
        }
        return t;
    }
    if (const auto q = doc.optional_numbers(node, "rotation", 4, where)) {
        double x = (*q)[0], y = (*q)[1], z = (*q)[2], w = (*q)[3];
        const double norm = std::sqrt(x * x + y * y + z * z + w * w);
        if (!(norm > 0.0)) {
            doc.fail(where + ".rotation", "the quaternion is zero");
        }
        x /= norm;
        y /= norm;
        z /= norm;
        w /= norm;
        t.m[0] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 0};
        t.m[1] = {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 0};
        t.m[2] = {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), 0};
    }
    if (const auto s = doc.optional_numbers(node, "scale", 3, where)) {
        for (std::size_t r = 0; r < 3; ++r) {
            for (std::size_t c = 0; c < 3; ++c) {
                t.m[r][c] *= (*s)[c];
            }
        }
    }
    if (const auto tr = doc.optional_numbers(node, "translation", 3, where)) {
        for (std::size_t r = 0; r < 3; ++r) {
            t.m[r][3] = (*tr)[r];
        }
    }
    return t;
}

/// The node indices listed in `holder[key]` (a scene's `nodes`, a node's `children`).
[[nodiscard]] std::vector<std::size_t> node_list(const GltfDocument& doc, const json& holder,
                                                 const std::string& key, const std::string& where) {
    std::vector<std::size_t> out;
    const auto it = holder.find(key);
    if (it == holder.end()) {
        return out;
    }
    if (!it->is_array()) {
        doc.fail(where + "." + key, "expected an array of node indices");
    }
    const std::size_t node_count = doc.root().contains("nodes") ? doc.root()["nodes"].size() : 0;
    for (std::size_t k = 0; k < it->size(); ++k) {
        const json& v = (*it)[k];
        const std::string item = where + "." + key + "[" + std::to_string(k) + "]";
        if (!v.is_number_unsigned() || v.get<std::uint64_t>() >= node_count) {
            doc.fail(item, "expected a node index below " + std::to_string(node_count) + ", got " +
                               v.dump());
        }
        out.push_back(static_cast<std::size_t>(v.get<std::uint64_t>()));
    }
    return out;
}

/// The nodes to walk: those of `scene`, else of `scenes[0]`, else every node that is no child.
[[nodiscard]] std::vector<std::size_t> root_nodes(const GltfDocument& doc) {
    const json& root = doc.root();
    std::optional<std::uint64_t> scene = doc.optional_uint(root, "scene", "");
    if (!scene && root.contains("scenes") && root["scenes"].is_array() && !root["scenes"].empty()) {
        scene = 0;
    }
    if (scene) {
        const auto index = static_cast<std::size_t>(*scene);
        const json& s = doc.element("scenes", index, "scene");
        return node_list(doc, s, "nodes", "scenes[" + std::to_string(index) + "]");
    }
    const auto nodes = root.find("nodes");
    if (nodes == root.end() || !nodes->is_array()) {
        return {};
    }
    std::vector<bool> is_child(nodes->size(), false);
    for (std::size_t i = 0; i < nodes->size(); ++i) {
        const std::string where = "nodes[" + std::to_string(i) + "]";
        for (std::size_t c : node_list(doc, doc.element("nodes", i, where), "children", where)) {
            is_child[c] = true;
        }
    }
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < is_child.size(); ++i) {
        if (!is_child[i]) {
            out.push_back(i);
        }
    }
    return out;
}

/// Appends the triangles of one primitive's vertex sequence `v` (already offset) to `faces`.
void triangulate(std::uint64_t mode, const std::vector<std::uint32_t>& v,
                 std::vector<Face>& faces) {
    const std::size_t n = v.size();
    if (mode == kModeTriangles) {
        for (std::size_t i = 0; i + 2 < n; i += 3) {
            faces.push_back({v[i], v[i + 1], v[i + 2]});
        }
    } else if (mode == kModeTriangleStrip) {
        // glTF 3.7.2.1: p_i = {v_i, v_(i + 1 + i % 2), v_(i + 2 - i % 2)}
        for (std::size_t i = 0; i + 2 < n; ++i) {
            const std::size_t odd = i % 2;
            faces.push_back({v[i], v[i + 1 + odd], v[i + 2 - odd]});
        }
    } else {
        // glTF 3.7.2.1: p_i = {v_(i + 1), v_(i + 2), v_0}
        for (std::size_t i = 0; i + 2 < n; ++i) {
            faces.push_back({v[i + 1], v[i + 2], v[0]});
        }
    }
}

/// Appends every triangle primitive of `meshes[mesh_index]`, transformed by `world`.
void append_mesh(GltfDocument& doc, std::size_t mesh_index, const Affine& world,
                 const std::string& node_where, TriangleMesh& out) {
    const json& mesh = doc.element("meshes", mesh_index, node_where + ".mesh");
    const std::string mesh_where = "meshes[" + std::to_string(mesh_index) + "]";
    const auto prims = mesh.find("primitives");
    if (prims == mesh.end() || !prims->is_array()) {
        doc.fail(mesh_where, "missing 'primitives' array");
    }
    for (std::size_t k = 0; k < prims->size(); ++k) {
        const json& prim = (*prims)[k];
        const std::string where = mesh_where + ".primitives[" + std::to_string(k) + "]";
        if (!prim.is_object()) {
            doc.fail(where, "expected an object");
        }
        const std::uint64_t mode = doc.optional_uint(prim, "mode", where).value_or(kModeTriangles);
        if (mode > kModeTriangleFan) {
            doc.fail(where + ".mode", std::to_string(mode) + " is not a glTF primitive mode");
        }
        const auto attributes = prim.find("attributes");
        if (attributes == prim.end() || !attributes->is_object()) {
            doc.fail(where, "missing 'attributes' object");
        }
        const auto position = doc.optional_uint(*attributes, "POSITION", where + ".attributes");
        if (mode < kModeTriangles || !position) {
            continue;  // points and lines; a primitive without positions is not rendered
        }
        const std::vector<Vec3d> positions =
            doc.read_positions(static_cast<std::size_t>(*position), where + ".attributes.POSITION");
        std::vector<std::uint32_t> sequence;
        if (const auto indices = doc.optional_uint(prim, "indices", where)) {
            sequence = doc.read_indices(static_cast<std::size_t>(*indices), positions.size(),
                                        where + ".indices");
        } else {
            if (positions.size() > std::numeric_limits<std::uint32_t>::max()) {
                doc.fail(where, "too many vertices for 32-bit indices");
            }
            sequence.resize(positions.size());
            for (std::size_t i = 0; i < sequence.size(); ++i) {
                sequence[i] = static_cast<std::uint32_t>(i);
            }
        }
        if (mode == kModeTriangles && sequence.size() % 3 != 0) {
            doc.fail(where, std::to_string(sequence.size()) +
                                " vertices is not a multiple of 3 (mode TRIANGLES)");
        }
        if (out.vertices.size() + positions.size() > std::numeric_limits<std::uint32_t>::max()) {
            doc.fail(where, "too many vertices in the scene for 32-bit indices");
        }
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (std::size_t i = 0; i < positions.size(); ++i) {
            const Vec3d p = world.apply(positions[i]);
            Vec3f f;
            if (!detail::to_float_coordinate(p.x, f.x) || !detail::to_float_coordinate(p.y, f.y) ||
                !detail::to_float_coordinate(p.z, f.z)) {
                doc.fail(where + ".attributes.POSITION",
                         "vertex " + std::to_string(i) + " is not finite or too large for float");
            }
            out.vertices.push_back(f);
        }
        for (auto& index : sequence) {
            index += base;
        }
        triangulate(mode, sequence, out.faces);
    }
}

[[nodiscard]] TriangleMesh load_scene(const std::filesystem::path& path) {
    GltfDocument doc(path);
    TriangleMesh mesh;
    const auto nodes = doc.root().find("nodes");
    std::vector<bool> visited(nodes != doc.root().end() && nodes->is_array() ? nodes->size() : 0,
                              false);
    // Depth-first pre-order with an explicit stack (children pushed in reverse).
    std::vector<std::pair<std::size_t, Affine>> stack;
    const std::vector<std::size_t> roots = root_nodes(doc);
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) {
        stack.emplace_back(*it, Affine{});
    }
    while (!stack.empty()) {
        const auto [index, parent] = stack.back();
        stack.pop_back();
        const std::string where = "nodes[" + std::to_string(index) + "]";
        const json& node = doc.element("nodes", index, where);
        if (visited[index]) {
            doc.fail(where, "is reached twice (the node hierarchy must be disjoint trees)");
        }
        visited[index] = true;
        const Affine world = compose(parent, local_transform(doc, node, where));
        if (const auto mesh_index = doc.optional_uint(node, "mesh", where)) {
            append_mesh(doc, static_cast<std::size_t>(*mesh_index), world, where, mesh);
        }
        const std::vector<std::size_t> children = node_list(doc, node, "children", where);
        for (auto it = children.rbegin(); it != children.rend(); ++it) {
            stack.emplace_back(*it, world);
        }
    }
    if (mesh.faces.empty()) {
        throw InputError(path.string(),
                         "no triangles in the scene (only points or lines, or no meshes)");
    }
    return mesh;
}

}  // namespace

TriangleMesh load_gltf(const std::filesystem::path& path) {
    try {
        return load_scene(path);
    } catch (const nlohmann::json::exception& e) {
        // A JSON value of an unexpected type that the checks above let through.
        throw InputError(path.string(), std::string("unexpected JSON content: ") + e.what());
    }
}

}  // namespace beamtrace
