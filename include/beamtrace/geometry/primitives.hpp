// Triangulated primitives: spheres (icospheres) and square plane patches.
#pragma once

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

/// A closed, outward-facing icosphere: 20 * 4^subdivisions triangles with vertices on the sphere.
[[nodiscard]] TriangleMesh make_icosphere(const Vec3d& center_m, double radius_m, int subdivisions);

/// A square patch of side `size_m` centred on `point_m`, facing `normal` (two triangles,
/// counter-clockwise seen from the side the normal points to).
[[nodiscard]] TriangleMesh make_square(const Vec3d& point_m, const Vec3d& normal, double size_m);

}  // namespace beamtrace
