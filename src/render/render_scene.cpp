#include "beamtrace/render/render_scene.hpp"

#include <cmath>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

void RenderScene::add_mesh(const TriangleMesh& part_mesh, std::uint32_t material,
                           std::uint32_t part) {
    mesh.append(part_mesh);
    face_material.resize(mesh.faces.size(), material);
    face_part.resize(mesh.faces.size(), part);
}

Aabb RenderScene::bounds() const {
    Aabb box = mesh.bounds();
    for (const auto& s : spheres) {
        const Vec3d r{s.sphere.radius_m, s.sphere.radius_m, s.sphere.radius_m};
        box.extend(Vec3f(s.sphere.center_m - r));
        box.extend(Vec3f(s.sphere.center_m + r));
    }
    for (const auto& p : planes) {
        if (!std::isfinite(p.plane.half_size_m)) {
            box.extend(Vec3f(p.plane.point_m));
            continue;
        }
        const double h = p.plane.half_size_m;
        const Vec3d u = p.plane.u_axis * h, w = p.plane.w_axis() * h;
        for (const Vec3d& c : {u + w, u - w, w - u, -u - w}) {
            box.extend(Vec3f(p.plane.point_m + c));
        }
    }
    return box;
}

void RenderScene::check() const {
    if (face_material.size() != mesh.faces.size() || face_part.size() != mesh.faces.size()) {
        throw ConfigError("render scene: per-face tables do not match the mesh");
    }
    const auto bad = [&](std::uint32_t m) { return m >= materials.size(); };
    bool any = false;
    for (auto m : face_material) {
        any = any || bad(m);
    }
    for (const auto& s : spheres) {
        any = any || bad(s.material) || !(s.sphere.radius_m > 0.0);
    }
    for (const auto& p : planes) {
        any = any || bad(p.material);
    }
    if (any) {
        throw ConfigError("render scene: a material index is out of range (" +
                          std::to_string(materials.size()) +
                          " materials) or a sphere radius is not positive");
    }
}

RenderScene build_render_scene(const Scene& scene, bool analytic) {
    RenderScene out;
    out.materials = scene.materials;
    if (out.materials.empty()) {
        out.materials.emplace_back();
    }
    std::vector<std::uint8_t> exact(scene.parts.size(), 0);
    for (const auto& s : scene.spheres) {
        // Exact sphere parts have no triangles: they are spheres whatever `analytic` says.
        if (analytic || scene.geometry.sphere_of_face(scene.parts.at(s.part).first_face)) {
            exact.at(s.part) = 1;
            out.spheres.push_back(
                {{s.center_m, s.radius_m}, s.attitude, scene.parts[s.part].material, s.part});
        }
    }
    if (analytic) {
        for (const auto& p : scene.planes) {
            exact.at(p.part) = 1;
            out.planes.push_back(
                {{p.point_m, normalize(p.normal), normalize(p.u_axis), 0.5 * p.size_m},
                 scene.parts[p.part].material,
                 p.part});
        }
    }
    // The faces of the other parts, in order, over the scene's vertices (the vertices of exact
    // parts stay unused: they lie on the exact surfaces, so bounds do not change). Instanced
    // parts are flattened: rendered scenes are small.
    TriangleMesh flat = scene.geometry.flatten();
    out.mesh.vertices = std::move(flat.vertices);
    for (std::size_t k = 0; k < scene.parts.size(); ++k) {
        const ScenePart& part = scene.parts[k];
        if (exact[k] != 0) {
            continue;
        }
        const auto first = flat.faces.begin() + part.first_face;
        out.mesh.faces.insert(out.mesh.faces.end(), first, first + part.face_count);
        out.face_material.resize(out.mesh.faces.size(), part.material);
        out.face_part.resize(out.mesh.faces.size(), static_cast<std::uint32_t>(k));
    }
    out.check();
    return out;
}

}  // namespace beamtrace
