#include "beamtrace/scene/scene.hpp"

#include <algorithm>
#include <limits>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"

namespace beamtrace {

void Scene::add_part(std::string name, const TriangleMesh& part) {
    ScenePart meta;
    meta.name = std::move(name);
    meta.part_id = static_cast<std::uint16_t>(std::min<std::size_t>(parts.size() + 1, 65535));
    add_part(std::move(meta), part);
}

void Scene::add_part(ScenePart meta, const TriangleMesh& part) {
    const std::size_t total = mesh.triangle_count() + part.triangle_count();
    if (total >= std::numeric_limits<std::uint32_t>::max() ||
        mesh.vertices.size() + part.vertices.size() >= std::numeric_limits<std::uint32_t>::max()) {
        throw InputError(meta.name, "the scene would exceed 2^32 - 1 triangles or vertices");
    }
    meta.first_face = static_cast<std::uint32_t>(mesh.triangle_count());
    meta.face_count = static_cast<std::uint32_t>(part.triangle_count());
    parts.push_back(std::move(meta));
    mesh.append(part);
}

std::size_t Scene::part_of_face(std::uint32_t face) const {
    const auto it =
        std::upper_bound(parts.begin(), parts.end(), face,
                         [](std::uint32_t f, const ScenePart& p) { return f < p.first_face; });
    return it == parts.begin() ? 0 : static_cast<std::size_t>(it - parts.begin()) - 1;
}

Scene load_scene_meshes(const std::vector<std::filesystem::path>& paths) {
    Scene scene;
    for (const auto& p : paths) {
        scene.add_part(p.string(), load_mesh(p));
    }
    return scene;
}

}  // namespace beamtrace
