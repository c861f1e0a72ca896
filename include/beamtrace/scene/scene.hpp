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
};

struct Scene {
    TriangleMesh mesh;
    std::vector<ScenePart> parts;

    /// Appends a part; its faces get the next IDs.
    void add_part(std::string name, const TriangleMesh& part);
    /// Index of the part that holds `face` (binary search).
    [[nodiscard]] std::size_t part_of_face(std::uint32_t face) const;
};

/// Loads and concatenates mesh files in order (face IDs 0-based over all of them).
[[nodiscard]] Scene load_scene_meshes(const std::vector<std::filesystem::path>& paths);

}  // namespace beamtrace
