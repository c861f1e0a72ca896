#include "beamtrace/scene/scene.hpp"

#include <algorithm>
#include <limits>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"

namespace beamtrace {
namespace {

/// The object number that follows the last part's copies.
std::uint32_t next_object(const std::vector<ScenePart>& parts) {
    return parts.empty() ? 0 : parts.back().first_object + parts.back().instance_count;
}

}  // namespace

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
    meta.first_object = next_object(parts);
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
    meta.first_object = next_object(parts);
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
    meta.first_object = next_object(parts);
    parts.push_back(std::move(meta));
}

void Scene::add_moving_part(ScenePart meta, std::uint32_t mesh, const RigidMotion& motion,
                            const Affine3& local, const std::vector<Vec3d>& offsets) {
    const auto m = static_cast<std::uint32_t>(motions.size());
    motions.push_back(motion);
    const Pose rest = motion.at(0.0);
    std::vector<Affine3> placed;
    placed.reserve(offsets.size());
    const std::size_t first = geometry.instances.size();
    for (const Vec3d& offset : offsets) {
        MovingInstance mi{mesh, 0, m, local, offset};
        placed.push_back(mi.to_world(rest));
        moving.push_back(mi);
    }
    meta.moving = true;
    add_instanced_part(std::move(meta), mesh, placed);
    for (std::size_t k = 0; k < offsets.size(); ++k) {
        moving[moving.size() - offsets.size() + k].first_face =
            geometry.instances[first + k].first_face;
    }
}

void Scene::detach_moving() {
    // The moving instances are the last ones (build_scene adds moving parts last); a second
    // call finds them gone.
    const auto& inst = geometry.instances;
    if (!moving.empty() && inst.size() >= moving.size() &&
        inst[inst.size() - moving.size()].first_face == moving.front().first_face) {
        geometry.instances.resize(inst.size() - moving.size());
    }
}

Aabb Scene::moving_bounds(double t0, double t1) const {
    Aabb box;
    for (const MovingInstance& mi : moving) {
        box.extend(mi.swept_bounds(geometry.meshes[mi.mesh].bounds(), motions[mi.motion], t0, t1));
    }
    return box;
}

const MovingInstance* Scene::moving_of_face(std::uint32_t face) const {
    if (moving.empty() || face < moving.front().first_face) {
        return nullptr;
    }
    const auto it =
        std::upper_bound(moving.begin(), moving.end(), face,
                         [](std::uint32_t f, const MovingInstance& i) { return f < i.first_face; });
    return &*(it - 1);
}

Vec3d Scene::normal_at(std::uint32_t face, const Vec3d& point, double time_s) const {
    const MovingInstance* mi = moving_of_face(face);
    if (mi == nullptr) {
        return geometry.normal_at(face, point);
    }
    const Affine3 to_world = mi->to_world(motions[mi->motion].at(time_s));
    const TriangleMesh& mesh = geometry.meshes[mi->mesh];
    const Face& f = mesh.faces[face - mi->first_face];
    const Vec3d a = to_world.apply_point(Vec3d(mesh.vertices[f[0]]));
    const Vec3d b = to_world.apply_point(Vec3d(mesh.vertices[f[1]]));
    const Vec3d c = to_world.apply_point(Vec3d(mesh.vertices[f[2]]));
    return normalize(cross(b - a, c - a));
}

Vec3d Scene::velocity_at(std::uint32_t face, const Vec3d& point, double time_s) const {
    const MovingInstance* mi = moving_of_face(face);
    if (mi == nullptr) {
        return {0, 0, 0};
    }
    return motions[mi->motion].point_velocity(point - mi->offset_m, time_s);
}

std::uint32_t Scene::object_of_face(std::uint32_t face) const {
    const ScenePart& part = parts[part_of_face(face)];
    if (part.instance_count <= 1 || part.face_count == 0) {
        return part.first_object;
    }
    const std::uint32_t per_copy = part.face_count / part.instance_count;
    return part.first_object + (face - part.first_face) / std::max<std::uint32_t>(per_copy, 1);
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
