// An indexed triangle set: the report's V (vertices) and F (faces, 0-based).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "beamtrace/core/aabb.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

using Face = std::array<std::uint32_t, 3>;

struct TriangleMesh {
    std::vector<Vec3f> vertices;  ///< metres
    std::vector<Face> faces;      ///< indices into `vertices`; face ID = position in this array

    [[nodiscard]] std::size_t triangle_count() const { return faces.size(); }
    [[nodiscard]] Aabb bounds() const;
    [[nodiscard]] Aabb triangle_bounds(std::size_t face) const;
    /// Appends `other`, re-indexing its faces; its face IDs start at the old triangle count.
    void append(const TriangleMesh& other);
    /// Throws if an index is out of range (loaders call this before returning).
    void check_indices(const char* what) const;
};

}  // namespace beamtrace
