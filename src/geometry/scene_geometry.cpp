#include "beamtrace/geometry/scene_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr std::uint64_t kMaxFaces = std::numeric_limits<std::uint32_t>::max();

}  // namespace

std::uint32_t SceneGeometry::add_mesh(TriangleMesh mesh) {
    if (mesh.triangle_count() >= kMaxFaces || mesh.vertices.size() >= kMaxFaces) {
        throw ConfigError("a mesh exceeds 2^32 - 1 triangles or vertices");
    }
    meshes.push_back(std::move(mesh));
    flat_open = false;
    return static_cast<std::uint32_t>(meshes.size() - 1);
}

void SceneGeometry::add_instance(std::uint32_t mesh, const Affine3& to_world) {
    if (mesh >= meshes.size()) {
        throw ConfigError("instance of mesh " + std::to_string(mesh) + ", but there are only " +
                          std::to_string(meshes.size()));
    }
    const double det = to_world.determinant();
    if (!std::isfinite(det) || det == 0.0) {
        throw ConfigError("instance transform is not invertible");
    }
    const std::uint64_t first = face_count();
    if (first + meshes[mesh].triangle_count() >= kMaxFaces) {
        throw ConfigError("the scene would exceed 2^32 - 1 triangles (" +
                          std::to_string(first + meshes[mesh].triangle_count()) + ")");
    }
    instances.push_back({mesh, to_world, static_cast<std::uint32_t>(first)});
    flat_open = false;
}

void SceneGeometry::append_flat(const TriangleMesh& part) {
    if (flat_open) {
        TriangleMesh& m = meshes.back();
        if (face_count() + part.triangle_count() >= kMaxFaces ||
            m.vertices.size() + part.vertices.size() >= kMaxFaces) {
            throw ConfigError("the scene would exceed 2^32 - 1 triangles or vertices");
        }
        m.append(part);
        return;
    }
    add_instance(add_mesh(part), Affine3{});
    flat_open = true;
}

void SceneGeometry::add_sphere(const Vec3f& center, float radius) {
    if (!(radius > 0.0f) || !std::isfinite(radius) || !std::isfinite(center.x) ||
        !std::isfinite(center.y) || !std::isfinite(center.z)) {
        throw ConfigError("an exact sphere needs a finite centre and a positive, finite radius");
    }
    const std::uint64_t face = face_count();
    if (face + 1 >= kMaxFaces) {
        throw ConfigError("the scene would exceed 2^32 - 1 faces");
    }
    spheres.push_back({center, radius, static_cast<std::uint32_t>(face)});
    flat_open = false;
}

std::uint64_t SceneGeometry::face_count() const {
    std::uint64_t n = 0;
    if (!instances.empty()) {
        const auto& last = instances.back();
        n = std::uint64_t{last.first_face} + meshes[last.mesh].triangle_count();
    }
    if (!spheres.empty()) {
        n = std::max<std::uint64_t>(n, std::uint64_t{spheres.back().face} + 1);
    }
    return n;
}

std::uint64_t SceneGeometry::triangle_count() const {
    return face_count() - spheres.size();
}

std::uint64_t SceneGeometry::stored_triangle_count() const {
    std::uint64_t n = 0;
    for (const auto& m : meshes) {
        n += m.triangle_count();
    }
    return n;
}

bool SceneGeometry::is_single_mesh() const {
    return instances.size() == 1 && instances[0].to_world.is_identity() && spheres.empty();
}

const ExactSphere* SceneGeometry::sphere_of_face(std::uint32_t face) const {
    const auto it =
        std::lower_bound(spheres.begin(), spheres.end(), face,
                         [](const ExactSphere& s, std::uint32_t f) { return s.face < f; });
    return it != spheres.end() && it->face == face ? &*it : nullptr;
}

std::size_t SceneGeometry::instance_of_face(std::uint32_t face) const {
    const auto it =
        std::upper_bound(instances.begin(), instances.end(), face,
                         [](std::uint32_t f, const MeshInstance& i) { return f < i.first_face; });
    return it == instances.begin() ? 0 : static_cast<std::size_t>(it - instances.begin()) - 1;
}

std::array<Vec3d, 3> SceneGeometry::triangle(std::uint32_t face) const {
    const MeshInstance& inst = instances[instance_of_face(face)];
    const TriangleMesh& m = meshes[inst.mesh];
    const Face& f = m.faces[face - inst.first_face];
    std::array<Vec3d, 3> out;
    for (std::size_t k = 0; k < 3; ++k) {
        out[k] = inst.to_world.apply_point(Vec3d(m.vertices[f[k]]));
    }
    return out;
}

Vec3d SceneGeometry::normal(std::uint32_t face) const {
    const auto t = triangle(face);
    return normalize(cross(t[1] - t[0], t[2] - t[0]));
}

Vec3d SceneGeometry::normal_at(std::uint32_t face, const Vec3d& point) const {
    if (const ExactSphere* s = sphere_of_face(face)) {
        return normalize(point - Vec3d(s->center));
    }
    return normal(face);
}

Aabb SceneGeometry::instance_bounds(std::size_t instance) const {
    const MeshInstance& inst = instances[instance];
    const Aabb local = meshes[inst.mesh].bounds();
    if (local.empty() || inst.to_world.is_identity()) {
        return local;
    }
    Aabb box;
    for (int c = 0; c < 8; ++c) {
        const Vec3d corner((c & 1) ? local.hi.x : local.lo.x, (c & 2) ? local.hi.y : local.lo.y,
                           (c & 4) ? local.hi.z : local.lo.z);
        const Vec3d w = inst.to_world.apply_point(corner);
        // Round outward so the float box contains the exact image of the corners.
        constexpr float kInf = std::numeric_limits<float>::infinity();
        for (std::size_t a = 0; a < 3; ++a) {
            const auto f = static_cast<float>(w[a]);
            box.lo[a] = std::min(box.lo[a], std::nextafter(f, -kInf));
            box.hi[a] = std::max(box.hi[a], std::nextafter(f, kInf));
        }
    }
    return box;
}

Aabb SceneGeometry::sphere_bounds(const ExactSphere& sphere) {
    // Rounded outward like instance_bounds: the float box contains the whole sphere.
    Aabb box;
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (std::size_t a = 0; a < 3; ++a) {
        const double c = sphere.center[a], r = sphere.radius;
        box.lo[a] = std::nextafter(static_cast<float>(c - r), -kInf);
        box.hi[a] = std::nextafter(static_cast<float>(c + r), kInf);
    }
    return box;
}

Aabb SceneGeometry::bounds() const {
    Aabb box;
    for (std::size_t i = 0; i < instances.size(); ++i) {
        box.extend(instance_bounds(i));
    }
    for (const auto& s : spheres) {
        box.extend(sphere_bounds(s));
    }
    return box;
}

TriangleMesh SceneGeometry::flatten() const {
    if (is_single_mesh()) {
        return meshes[instances[0].mesh];
    }
    TriangleMesh out;
    std::size_t vertex_count = 0;
    for (const auto& inst : instances) {
        vertex_count += meshes[inst.mesh].vertices.size();
    }
    out.vertices.reserve(vertex_count + spheres.size());
    out.faces.reserve(face_count());
    auto sphere = spheres.begin();
    // Exact spheres with IDs below `face`, as degenerate triangles at their centres.
    const auto spheres_before = [&](std::uint64_t face) {
        for (; sphere != spheres.end() && sphere->face < face; ++sphere) {
            const auto c = static_cast<std::uint32_t>(out.vertices.size());
            out.vertices.push_back(sphere->center);
            out.faces.push_back({c, c, c});
        }
    };
    for (const auto& inst : instances) {
        spheres_before(inst.first_face);
        const TriangleMesh& m = meshes[inst.mesh];
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (const auto& v : m.vertices) {
            out.vertices.emplace_back(inst.to_world.apply_point(Vec3d(v)));
        }
        for (const auto& f : m.faces) {
            out.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
        }
    }
    spheres_before(face_count());
    return out;
}

}  // namespace beamtrace
