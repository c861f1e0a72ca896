#include <map>

#include "beamtrace/core/error.hpp"
#include "beamtrace/geometry/primitives.hpp"
#include "beamtrace/geometry/ray_plane.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "beamtrace/scene/raster_terrain.hpp"
#include "beamtrace/scene/scene_builder.hpp"

namespace beamtrace {
namespace {

/// Keeps the exact sphere/plane of a part whose transform keeps it one (uniform scale).
void add_analytic_copy(const PartSpec& p, std::uint32_t part, Scene& scene) {
    const Vec3d& k = p.transform.scale;
    if (!(k.x == k.y && k.y == k.z)) {
        return;
    }
    const Quat q = Quat::from_rpy(p.transform.rotate);
    if (p.kind == PartKind::sphere) {
        scene.spheres.push_back({p.transform.apply(p.center_m), p.radius_m * k.x, q, part});
    } else if (p.kind == PartKind::plane) {
        const PlanePatch local = make_plane_patch(p.point_m, p.normal, p.size_m);
        scene.planes.push_back({p.transform.apply(p.point_m), q.rotate(local.normal),
                                q.rotate(local.u_axis), p.size_m * k.x, part});
    }
}

}  // namespace

Scene build_scene(const SceneSpec& spec) {
    Scene scene;
    scene.origin_m = spec.origin_m;
    scene.materials.clear();
    for (const auto& m : spec.materials) {
        scene.materials.push_back(
            {m.name, m.reflectance, m.specular_weight, m.specular_exponent, m.pattern});
    }
    // Each file is read once, however many parts use it.
    std::map<std::filesystem::path, TriangleMesh> files;
    for (const auto& p : spec.parts) {
        TriangleMesh local;
        switch (p.kind) {
            case PartKind::mesh: {
                auto it = files.find(p.file);
                if (it == files.end()) {
                    it = files.emplace(p.file, load_mesh(p.file)).first;
                }
                local = it->second;
                break;
            }
            case PartKind::raster:
                local = raster_to_mesh(load_raster(p.file), spec.origin_m);
                break;
            case PartKind::sphere:
                local = make_icosphere(p.center_m, p.radius_m, p.sphere_subdivisions);
                break;
            case PartKind::plane:
                local = make_square(p.point_m, p.normal, p.size_m);
                break;
        }
        for (auto& v : local.vertices) {
            v = Vec3f(p.transform.apply(Vec3d(v)));
        }
        add_analytic_copy(p, static_cast<std::uint32_t>(scene.parts.size()), scene);
        ScenePart meta;
        meta.name = p.name;
        meta.label = p.label;
        meta.part_id = p.part_id;
        for (std::size_t i = 0; i < spec.materials.size(); ++i) {
            if (spec.materials[i].name == p.material) {
                meta.material = static_cast<std::uint32_t>(i);
            }
        }
        scene.add_part(std::move(meta), local);
    }
    return scene;
}

Scene load_scene_file(const std::filesystem::path& path) {
    return build_scene(load_scene_spec(path));
}

}  // namespace beamtrace
