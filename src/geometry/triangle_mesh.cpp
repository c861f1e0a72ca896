#include "beamtrace/geometry/triangle_mesh.hpp"

#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

Aabb TriangleMesh::bounds() const {
    Aabb b;
    for (const auto& v : vertices) {
        b.extend(v);
    }
    return b;
}

Aabb TriangleMesh::triangle_bounds(std::size_t face) const {
    Aabb b;
    for (auto idx : faces[face]) {
        b.extend(vertices[idx]);
    }
    return b;
}

void TriangleMesh::append(const TriangleMesh& other) {
    const auto base = static_cast<std::uint32_t>(vertices.size());
    vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
    faces.reserve(faces.size() + other.faces.size());
    for (const auto& f : other.faces) {
        faces.push_back({f[0] + base, f[1] + base, f[2] + base});
    }
}

void TriangleMesh::check_indices(const char* what) const {
    const auto n = vertices.size();
    for (std::size_t i = 0; i < faces.size(); ++i) {
        for (auto idx : faces[i]) {
            if (idx >= n) {
                throw InputError(what, "face " + std::to_string(i) + " refers to vertex " +
                                           std::to_string(idx) + " but there are only " +
                                           std::to_string(n) + " vertices");
            }
        }
    }
}

}  // namespace beamtrace
