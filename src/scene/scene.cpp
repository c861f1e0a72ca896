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
    const std::uint64_t first = geometry.face_count();
    try {
        geometry.append_flat(part);
    } catch (const ConfigError& e) {
        throw InputError(meta.name, e.what());
    }
    meta.first_face = static_cast<std::uint32_t>(first);
    meta.face_count = static_cast<std::uint32_t>(part.triangle_count());
    meta.instance_count = 1;
    parts.push_back(std::move(meta));
}

void Scene::add_instanced_part(ScenePart meta, std::uint32_t mesh,
                               const std::vector<Affine3>& to_world) {
    const std::uint64_t first = geometry.face_count();
    try {
        for (const auto& t : to_world) {
            geometry.add_instance(mesh, t);
        }
    } catch (const ConfigError& e) {
        throw InputError(meta.name, e.what());
    }
    meta.first_face = static_cast<std::uint32_t>(first);
    meta.face_count = static_cast<std::uint32_t>(geometry.face_count() - first);
    meta.instance_count = static_cast<std::uint32_t>(to_world.size());
    parts.push_back(std::move(meta));
}

void Scene::add_sphere_part(ScenePart meta, const std::vector<ExactSphere>& balls) {
    const std::uint64_t first = geometry.face_count();
    try {
        for (const auto& s : balls) {
            geometry.add_sphere(s.center, s.radius);
        }
    } catch (const ConfigError& e) {
        throw InputError(meta.name, e.what());
    }
    meta.first_face = static_cast<std::uint32_t>(first);
    meta.face_count = static_cast<std::uint32_t>(balls.size());
    meta.instance_count = static_cast<std::uint32_t>(balls.size());
    parts.push_back(std::move(meta));
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
