// The surfaces of a scene: triangles as unique meshes placed by instances, so a mesh used many
// times is stored once, and spheres traced exactly. Face IDs are global and given in the order
// things are added: instance k covers [first_face, first_face + its mesh's triangle count), as if
// every instance had been copied into one mesh, and an exact sphere takes one face ID of its own.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "beamtrace/core/aabb.hpp"
#include "beamtrace/core/affine.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

struct MeshInstance {
    std::uint32_t mesh = 0;        ///< index into SceneGeometry::meshes
    Affine3 to_world;              ///< object coordinates -> scene coordinates (identity: none)
    std::uint32_t first_face = 0;  ///< global face ID of the mesh's face 0
};

/// A sphere traced exactly (not as triangles), in scene coordinates.
struct ExactSphere {
    Vec3f center;
    float radius = 1.0f;
    std::uint32_t face = 0;  ///< its global face ID
};

struct SceneGeometry {
    std::vector<TriangleMesh> meshes;
    std::vector<MeshInstance> instances;  ///< sorted by first_face
    std::vector<ExactSphere> spheres;     ///< sorted by face (IDs between instances' ranges)
    /// True while the last instance is a mesh made by append_flat, which the next append_flat
    /// may extend (add_mesh and add_instance end it).
    bool flat_open = false;

    /// Adds a mesh (not yet placed); returns its index.
    std::uint32_t add_mesh(TriangleMesh mesh);
    /// Places mesh `mesh` with `to_world`; its faces get the next global IDs. Throws ConfigError
    /// when the transform is singular or the scene would exceed 2^32 - 1 faces.
    void add_instance(std::uint32_t mesh, const Affine3& to_world);
    /// Appends triangles given in scene coordinates: they join the last instance when that is an
    /// unshared mesh placed with the identity, so consecutive flat parts make one mesh.
    void append_flat(const TriangleMesh& part);
    /// Adds an exact sphere; it gets the next global face ID. Throws ConfigError when the radius
    /// is not positive or a coordinate not finite, or the scene would exceed 2^32 - 1 faces.
    void add_sphere(const Vec3f& center, float radius);

    /// Global face count: every instance's triangles and the exact spheres.
    [[nodiscard]] std::uint64_t face_count() const;
    /// Triangles of all instances (face_count() less the exact spheres).
    [[nodiscard]] std::uint64_t triangle_count() const;
    /// Triangles actually stored (each unique mesh once).
    [[nodiscard]] std::uint64_t stored_triangle_count() const;
    /// True when the geometry is one mesh placed once with the identity and nothing else.
    [[nodiscard]] bool is_single_mesh() const;
    /// The exact sphere with global face ID `face`, or nullptr when `face` is a triangle.
    [[nodiscard]] const ExactSphere* sphere_of_face(std::uint32_t face) const;
    /// Index of the instance holding triangle `face` (binary search; `face` must be a triangle).
    [[nodiscard]] std::size_t instance_of_face(std::uint32_t face) const;
    /// The corners of triangle `face` in scene coordinates.
    [[nodiscard]] std::array<Vec3d, 3> triangle(std::uint32_t face) const;
    /// Unit geometric normal of triangle `face` in scene coordinates ((b - a) x (c - a)).
    [[nodiscard]] Vec3d normal(std::uint32_t face) const;
    /// Unit normal of face `face` at `point` (scene coordinates) on it: a triangle's geometric
    /// normal, or a sphere's outward normal through the point.
    [[nodiscard]] Vec3d normal_at(std::uint32_t face, const Vec3d& point) const;
    /// World bounds of one instance (its mesh's box corners mapped by the transform).
    [[nodiscard]] Aabb instance_bounds(std::size_t instance) const;
    /// World bounds of an exact sphere.
    [[nodiscard]] static Aabb sphere_bounds(const ExactSphere& sphere);
    /// Bounds of the whole scene.
    [[nodiscard]] Aabb bounds() const;
    /// Every instance copied into one mesh, face IDs preserved: an exact sphere's ID holds a
    /// degenerate triangle at its centre, which no ray meets (the oracle backends trace the
    /// spheres themselves).
    [[nodiscard]] TriangleMesh flatten() const;
};

}  // namespace beamtrace
