#include "beamtrace/scene/scene_builder.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

#include "beamtrace/core/crs.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/geometry/primitives.hpp"
#include "beamtrace/geometry/ray_plane.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "beamtrace/scene/raster_terrain.hpp"

namespace beamtrace {
namespace {

/// Takes a raster's CRS as the scene's, unless the scene file gives `crs:` (which wins); rasters
/// that name different CRSs without it are refused.
void take_raster_crs(const Crs& crs, const PartSpec& p, const SceneSpec& spec, Scene& scene) {
    if (!spec.crs.empty() || crs.empty()) {
        return;
    }
    if (scene.crs.empty()) {
        scene.crs = crs;
    } else if (scene.crs != crs) {
        throw InputError(spec.source.string(),
                         "part '" + p.name + "': its raster's CRS " + describe_crs(crs) +
                             " differs from " + describe_crs(scene.crs) +
                             " of an earlier raster; say which is meant with crs:");
    }
}

TriangleMesh part_mesh(const PartSpec& p, const SceneSpec& spec, Scene& scene) {
    switch (p.kind) {
        case PartKind::mesh:
            return load_mesh(p.file);
        case PartKind::raster: {
            const Raster raster = load_raster(p.file);
            take_raster_crs(raster.crs, p, spec, scene);
            return raster_to_mesh(raster, spec.origin_m);
        }
        case PartKind::sphere:
            return make_icosphere(p.center_m, p.radius_m, p.sphere_subdivisions);
        case PartKind::plane:
            return make_square(p.point_m, p.normal, p.size_m);
    }
    return {};
}

[[nodiscard]] bool fits_float(double v) {
    return std::isfinite(v) && std::fabs(v) <= std::numeric_limits<float>::max();
}

[[nodiscard]] bool fits_float(const Vec3d& v) {
    return fits_float(v.x) && fits_float(v.y) && fits_float(v.z);
}

[[nodiscard]] std::string show(const Vec3d& v) {
    std::array<char, 96> text{};
    std::snprintf(text.data(), text.size(), "(%g, %g, %g)", v.x, v.y, v.z);
    return text.data();
}

/// The error for part `p` whose `what` does not fit in float.
[[nodiscard]] InputError not_float(const PartSpec& p, const SceneSpec& spec,
                                   const std::string& what) {
    return InputError(spec.source.string(), "part '" + p.name + "': " + what +
                                                " is not finite in float (magnitude at most " +
                                                "3.4e38 m)");
}

/// Refuses a part whose coordinates, radius, size, scale or array step are not finite once
/// converted to float (a sphere at 1e300), naming the part and the setting.
void check_part_numbers(const PartSpec& p, const SceneSpec& spec) {
    const auto vec = [&](const char* key, const Vec3d& v) {
        if (!fits_float(v)) {
            throw not_float(p, spec, std::string(key) + " " + show(v));
        }
    };
    const auto num = [&](const char* key, double v) { vec(key, {v, 0.0, 0.0}); };
    if (p.kind == PartKind::sphere) {
        vec("center_m", p.center_m);
        num("radius_m", p.radius_m);
    } else if (p.kind == PartKind::plane) {
        vec("point_m", p.point_m);
        vec("normal", p.normal);
        num("size_m", p.size_m);
    }
    vec("translate_m", p.transform.translate_m);
    vec("scale", p.transform.scale);
    vec("array step_m", p.array.step_m);
    const Vec3d last(static_cast<double>(p.array.count[0] - 1) * p.array.step_m.x,
                     static_cast<double>(p.array.count[1] - 1) * p.array.step_m.y,
                     static_cast<double>(p.array.count[2] - 1) * p.array.step_m.z);
    vec("the last array copy's offset", p.transform.translate_m + last);
}

/// The part's vertices in scene coordinates; refuses any that is not finite in float.
void to_scene(const PartSpec& p, const SceneSpec& spec, TriangleMesh& local) {
    for (std::size_t i = 0; i < local.vertices.size(); ++i) {
        const Vec3d v = p.transform.apply(Vec3d(local.vertices[i]));
        if (!fits_float(v)) {
            throw not_float(p, spec, "vertex " + std::to_string(i) + " at " + show(v));
        }
        local.vertices[i] = Vec3f(v);
    }
}

/// Refuses an instanced part whose mesh, moved by its first or last copy's transform (the
/// extremes of the grid), leaves float range.
void check_copies(const PartSpec& p, const SceneSpec& spec, const TriangleMesh& mesh,
                  const std::vector<Affine3>& copies) {
    const Aabb box = mesh.bounds();
    if (mesh.vertices.empty() || copies.empty()) {
        return;
    }
    for (const Affine3* t : {&copies.front(), &copies.back()}) {
        for (int c = 0; c < 8; ++c) {
            const Vec3d corner((c & 1) != 0 ? box.hi.x : box.lo.x,
                               (c & 2) != 0 ? box.hi.y : box.lo.y,
                               (c & 4) != 0 ? box.hi.z : box.lo.z);
            const Vec3d w = t->apply_point(corner);
            if (!fits_float(corner) || !fits_float(w)) {
                throw not_float(p, spec, "a copy's corner at " + show(w));
            }
        }
    }
}

/// The transforms of every copy of an arrayed part, x fastest.
std::vector<Affine3> copy_transforms(const PartSpec& p) {
    const Affine3 base = p.transform.to_affine();
    std::vector<Affine3> out;
    out.reserve(p.array.copies());
    for (long k = 0; k < p.array.count[2]; ++k) {
        for (long j = 0; j < p.array.count[1]; ++j) {
            for (long i = 0; i < p.array.count[0]; ++i) {
                Affine3 t = base;
                t.translation = t.translation + Vec3d(static_cast<double>(i) * p.array.step_m.x,
                                                      static_cast<double>(j) * p.array.step_m.y,
                                                      static_cast<double>(k) * p.array.step_m.z);
                out.push_back(t);
            }
        }
    }
    return out;
}

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

/// Keeps the analytic copy of a part with one copy (see add_analytic_copy) and notes in `meta`
/// where its analytic copies are (what its material's pattern is laid on).
void add_analytic_copies(const PartSpec& p, ScenePart& meta, Scene& scene) {
    const auto spheres = static_cast<std::int64_t>(scene.spheres.size());
    const auto planes = static_cast<std::int64_t>(scene.planes.size());
    if (p.exact_sphere) {
        meta.first_sphere = spheres;  // add_exact_spheres appends one per copy
        return;
    }
    if (p.array.copies() == 1) {
        add_analytic_copy(p, static_cast<std::uint32_t>(scene.parts.size()), scene);
    }
    if (static_cast<std::int64_t>(scene.spheres.size()) > spheres) {
        meta.first_sphere = spheres;
    }
    if (static_cast<std::int64_t>(scene.planes.size()) > planes) {
        meta.plane = planes;
    }
}

/// One exact sphere per copy of the part (the spec checked that the scale is uniform), and its
/// analytic copy for the renderers.
void add_exact_spheres(const PartSpec& p, ScenePart meta, Scene& scene) {
    const auto part = static_cast<std::uint32_t>(scene.parts.size());
    const Quat q = Quat::from_rpy(p.transform.rotate);
    const double radius_m = p.radius_m * p.transform.scale.x;
    std::vector<ExactSphere> spheres;
    for (const Affine3& t : copy_transforms(p)) {
        const Vec3d c = t.apply_point(p.center_m);
        spheres.push_back({Vec3f(c), static_cast<float>(radius_m), 0});
        scene.spheres.push_back({c, radius_m, q, part});
    }
    scene.add_sphere_part(std::move(meta), spheres);
}

/// The mesh files used by several parts and where they are stored.
struct MeshStore {
    std::map<std::filesystem::path, int> uses;
    std::map<std::filesystem::path, std::uint32_t> stored;  // file -> SceneGeometry mesh index

    /// The index of part p's mesh in the scene's geometry, loading it the first time.
    std::uint32_t mesh_of(const PartSpec& p, const SceneSpec& spec, Scene& scene) {
        const bool shared_file = p.kind == PartKind::mesh && uses[p.file] > 1;
        const auto it = shared_file ? stored.find(p.file) : stored.end();
        if (it != stored.end()) {
            return it->second;
        }
        const std::uint32_t mesh = scene.geometry.add_mesh(part_mesh(p, spec, scene));
        if (shared_file) {
            stored.emplace(p.file, mesh);
        }
        return mesh;
    }
};

/// The part's table entry: name, label, ID and material.
ScenePart part_meta(const PartSpec& p, const SceneSpec& spec) {
    ScenePart meta;
    meta.name = p.name;
    meta.label = p.label;
    meta.part_id = p.part_id;
    for (std::size_t i = 0; i < spec.materials.size(); ++i) {
        if (spec.materials[i].name == p.material) {
            meta.material = static_cast<std::uint32_t>(i);
        }
    }
    return meta;
}

void add_still_part(const PartSpec& p, const SceneSpec& spec, MeshStore& store, Scene& scene) {
    check_part_numbers(p, spec);
    ScenePart meta;
    add_analytic_copies(p, meta, scene);
    const ScenePart named = part_meta(p, spec);
    meta.name = named.name;
    meta.label = named.label;
    meta.part_id = named.part_id;
    meta.material = named.material;
    if (p.kind == PartKind::sphere && p.exact_sphere) {
        add_exact_spheres(p, std::move(meta), scene);
        return;
    }
    const bool shared_file = p.kind == PartKind::mesh && store.uses[p.file] > 1;
    if (!shared_file && p.array.copies() == 1) {
        TriangleMesh local = part_mesh(p, spec, scene);
        to_scene(p, spec, local);
        scene.add_part(std::move(meta), local);
        return;
    }
    const std::uint32_t mesh = store.mesh_of(p, spec, scene);
    std::vector<Affine3> copies = copy_transforms(p);
    check_copies(p, spec, scene.geometry.meshes[mesh], copies);
    scene.add_instanced_part(std::move(meta), mesh, std::move(copies));
}

/// A part with a motion: one moving instance per array copy (the motion after the part's
/// transform, the copy's step after the motion).
void add_moving_part(const PartSpec& p, const SceneSpec& spec, MeshStore& store, Scene& scene) {
    check_part_numbers(p, spec);
    const PartMotion& pm = *p.motion;
    RigidMotion motion;
    Affine3 local = p.transform.to_affine();
    if (!pm.keys.empty()) {
        motion.keys = pm.keys;
    } else {
        motion.pivot_m = pm.pivot_m.value_or(p.transform.translate_m);
        motion.velocity_mps = pm.velocity_mps;
        motion.spin_axis = pm.spin_axis;
        motion.spin_rate_rad_s = pm.spin_rate_rad_s;
        local.translation = local.translation - motion.pivot_m;
    }
    std::vector<Vec3d> offsets;
    for (const Affine3& t : copy_transforms(p)) {
        offsets.push_back(t.translation - p.transform.translate_m);
    }
    const std::uint32_t mesh = store.mesh_of(p, spec, scene);
    std::vector<Affine3> rest;
    for (const Vec3d& o : offsets) {
        rest.push_back(MovingInstance{mesh, 0, 0, local, o}.to_world(motion.at(0.0)));
    }
    check_copies(p, spec, scene.geometry.meshes[mesh], rest);
    scene.add_moving_part(part_meta(p, spec), mesh, motion, local, offsets);
}

}  // namespace

Scene build_scene(const SceneSpec& spec) {
    Scene scene;
    scene.origin_m = spec.origin_m;
    scene.crs = spec.crs;
    scene.materials = spec.materials;  // physics Materials: the one model
    // A mesh file used by several parts, and any part with array copies, is stored once and
    // instanced; every other part is copied into the scene in scene coordinates. Moving parts
    // come last (their faces take the highest IDs), each a true instance per copy.
    MeshStore store;
    for (const auto& p : spec.parts) {
        if (p.kind == PartKind::mesh) {
            ++store.uses[p.file];
        }
    }
    for (const auto& p : spec.parts) {
        if (!p.motion) {
            add_still_part(p, spec, store, scene);
        }
    }
    for (const auto& p : spec.parts) {
        if (p.motion) {
            add_moving_part(p, spec, store, scene);
        }
    }
    return scene;
}

Scene load_scene_file(const std::filesystem::path& path) {
    return build_scene(load_scene_spec(path));
}

}  // namespace beamtrace
