// Moller-Trumbore ray/triangle intersection of one ray against every face, after BrainStorm's
// `ray_intersect.m`: cull modes, a parallel tolerance scaled by the longest first edge, and
// barycentric bounds with EPS = 1e-6. Unlike that code, only hits at t >= 0 are returned.
#pragma once

#include <cstdint>
#include <vector>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/geometry/ray_triangle.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

struct MtHit {
    std::uint32_t face = 0;
    double t = 0, u = 0, v = 0;
    Vec3d point;  ///< (1-u-v) V0 + u V1 + v V2
};

struct MollerTrumboreConfig {
    double parallel_tol = 1e-6;     ///< multiplied by the longest first edge |V1-V0| of the mesh
    double barycentric_eps = 1e-6;  ///< slack on u, v >= 0 and u + v <= 1
};

/// Every face that the ray `origin + t * direction` (t >= 0) meets, in face order.
/// `direction` need not be unit length; it is normalised, so t is a distance.
[[nodiscard]] std::vector<MtHit> ray_intersect_all(const TriangleMesh& mesh, const Vec3d& origin,
                                                   const Vec3d& direction, Facing facing,
                                                   const MollerTrumboreConfig& config = {});

}  // namespace beamtrace
