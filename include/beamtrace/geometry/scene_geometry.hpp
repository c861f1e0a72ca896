// The triangles of a scene as unique meshes placed by instances, so a mesh used many times is
// stored once. Face IDs are global: instance k covers [first_face, first_face + its mesh's
// triangle count), in instance order, as if every instance had been copied into one mesh.
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

struct SceneGeometry {
    std::vector<TriangleMesh> meshes;
    std::vector<MeshInstance> instances;  ///< sorted by first_face, ranges back to back
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

    /// Global face count (all instances).
    [[nodiscard]] std::uint64_t triangle_count() const;
    /// Triangles actually stored (each unique mesh once).
    [[nodiscard]] std::uint64_t stored_triangle_count() const;
    /// True when the geometry is one mesh placed once with the identity (no instancing at all).
    [[nodiscard]] bool is_single_mesh() const;
    /// Index of the instance holding global face `face` (binary search).
    [[nodiscard]] std::size_t instance_of_face(std::uint32_t face) const;
    /// The corners of global face `face` in scene coordinates.
    [[nodiscard]] std::array<Vec3d, 3> triangle(std::uint32_t face) const;
    /// Unit geometric normal of global face `face` in scene coordinates ((b - a) x (c - a)).
    [[nodiscard]] Vec3d normal(std::uint32_t face) const;
    /// World bounds of one instance (its mesh's box corners mapped by the transform).
    [[nodiscard]] Aabb instance_bounds(std::size_t instance) const;
    /// Bounds of the whole scene.
    [[nodiscard]] Aabb bounds() const;
    /// Every instance copied into one mesh (face IDs preserved); for the oracle backends.
    [[nodiscard]] TriangleMesh flatten() const;
};

}  // namespace beamtrace
