// What the renderer traces: triangles (through an accel Backend) plus exact spheres and planes,
// each tagged with a material and the scene part it came from.
#pragma once

#include <cstdint>
#include <vector>

#include "beamtrace/core/aabb.hpp"
#include "beamtrace/core/quat.hpp"
#include "beamtrace/geometry/ray_plane.hpp"
#include "beamtrace/geometry/ray_sphere.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"
#include "beamtrace/scene/scene.hpp"

namespace beamtrace {

struct RenderSphere {
    Sphere sphere;
    Quat attitude;  ///< orients the albedo pattern (local z = stripe axis)
    std::uint32_t material = 0;
    std::uint32_t part = 0;
};

struct RenderPlane {
    PlanePatch plane;
    std::uint32_t material = 0;
    std::uint32_t part = 0;
};

struct RenderScene {
    TriangleMesh mesh;                         ///< triangles traced by the backend
    std::vector<std::uint32_t> face_material;  ///< per face of `mesh`
    std::vector<std::uint32_t> face_part;      ///< per face of `mesh`
    std::vector<RenderSphere> spheres;
    std::vector<RenderPlane> planes;
    std::vector<Material> materials{Material{}};  ///< the scene's (their patterns, colours)

    /// Appends triangles with one material and part tag.
    void add_mesh(const TriangleMesh& part_mesh, std::uint32_t material, std::uint32_t part);
    /// Bounds of the triangles, spheres and bounded planes (infinite planes are left out).
    [[nodiscard]] Aabb bounds() const;
    /// Throws ConfigError when a material index is out of range or the tables disagree.
    void check() const;
};

/// The one place that reads a Scene: triangles of every part except those with an analytic copy
/// (Scene::spheres / Scene::planes), which are traced exactly instead (or, with
/// `analytic = false`, as their triangles; exact sphere parts have none and stay exact).
[[nodiscard]] RenderScene build_render_scene(const Scene& scene, bool analytic = true);

}  // namespace beamtrace
