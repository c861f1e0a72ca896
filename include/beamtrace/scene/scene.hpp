// A scene for the core scanner: the report's single triangle set plus a table of the parts it
// was concatenated from (so face IDs can be traced back to a mesh file).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

struct ScenePart {
    std::string name;              ///< file path or procedural part name
    std::uint32_t first_face = 0;  ///< face IDs [first_face, first_face + face_count)
    std::uint32_t face_count = 0;
    std::uint8_t label = 1;      ///< class written as LAS classification (1 = unclassified)
    std::uint16_t part_id = 0;   ///< written as LAS point source ID
    std::uint32_t material = 0;  ///< index into Scene::materials
};

struct SceneMaterial {
    std::string name = "default";
    double reflectance = 0.5;
    double specular_weight = 0.0;
    double specular_exponent = 10.0;
};

struct Scene {
    TriangleMesh mesh;
    std::vector<ScenePart> parts;
    std::vector<SceneMaterial> materials{SceneMaterial{}};
    /// World position of the local origin: triangles are stored relative to it (float precision
    /// for UTM-sized coordinates) and outputs add it back.
    Vec3d origin_m{0, 0, 0};

    /// Appends a part; its faces get the next IDs.
    void add_part(std::string name, const TriangleMesh& part);
    /// Appends a part with its label, ID and material (first_face/face_count are filled in).
    void add_part(ScenePart meta, const TriangleMesh& part);
    /// Index of the part that holds `face` (binary search).
    [[nodiscard]] std::size_t part_of_face(std::uint32_t face) const;
};

/// Loads and concatenates mesh files in order (face IDs 0-based over all of them).
[[nodiscard]] Scene load_scene_meshes(const std::vector<std::filesystem::path>& paths);

}  // namespace beamtrace
