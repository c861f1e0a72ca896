#include "beamtrace/geometry/moller_trumbore.hpp"

#include <algorithm>
#include <cmath>

namespace beamtrace {

std::vector<MtHit> ray_intersect_all(const TriangleMesh& mesh, const Vec3d& origin,
                                     const Vec3d& direction, Facing facing,
                                     const MollerTrumboreConfig& config) {
    std::vector<MtHit> hits;
    const Vec3d d = normalize(direction);
    double longest_edge = 0.0;
    for (const auto& f : mesh.faces) {
        const Vec3d e1 = Vec3d(mesh.vertices[f[1]]) - Vec3d(mesh.vertices[f[0]]);
        longest_edge = std::max(longest_edge, length(e1));
    }
    const double tol = config.parallel_tol * longest_edge;
    const double eps = config.barycentric_eps;
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        const auto& f = mesh.faces[i];
        const Vec3d v0(mesh.vertices[f[0]]), v1(mesh.vertices[f[1]]), v2(mesh.vertices[f[2]]);
        const Vec3d e1 = v1 - v0, e2 = v2 - v0;
        const Vec3d p = cross(d, e2);
        const double det = dot(e1, p);
        const bool ok = facing == Facing::both    ? (det < -tol || det > tol)
                        : facing == Facing::front ? det > tol
                                                  : det < -tol;
        if (!ok) {
            continue;
        }
        const Vec3d T = origin - v0;
        const double u = dot(T, p) / det;
        if (u < -eps || u > 1.0 + eps) {
            continue;
        }
        const Vec3d q = cross(T, e1);
        const double v = dot(d, q) / det;
        if (v < -eps || u + v > 1.0 + eps) {
            continue;
        }
        const double t = dot(e2, q) / det;
        if (t < 0.0) {
            continue;
        }
        hits.push_back(
            {static_cast<std::uint32_t>(i), t, u, v, v0 * (1.0 - u - v) + v1 * u + v2 * v});
    }
    return hits;
}

}  // namespace beamtrace
