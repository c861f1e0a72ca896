#include "beamtrace/geometry/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace beamtrace {

TriangleMesh make_icosphere(const Vec3d& center_m, double radius_m, int subdivisions) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                            {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                            {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : v) {
        p = normalize(p);
    }
    std::vector<Face> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            if (const auto it = mid.find(key); it != mid.end()) {
                return it->second;
            }
            v.push_back(normalize((v[a] + v[b]) * 0.5));
            const auto idx = static_cast<std::uint32_t>(v.size() - 1);
            mid.emplace(key, idx);
            return idx;
        };
        std::vector<Face> next;
        next.reserve(faces.size() * 4);
        for (const auto& f : faces) {
            const auto a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
            next.push_back({f[0], a, c});
            next.push_back({f[1], b, a});
            next.push_back({f[2], c, b});
            next.push_back({a, b, c});
        }
        faces = std::move(next);
    }
    TriangleMesh m;
    m.faces = std::move(faces);
    m.vertices.reserve(v.size());
    for (const auto& p : v) {
        m.vertices.emplace_back(center_m + p * radius_m);
    }
    return m;
}

TriangleMesh make_square(const Vec3d& point_m, const Vec3d& normal, double size_m) {
    const Vec3d n = normalize(normal);
    // Any unit vector perpendicular to n, then the third axis.
    const Vec3d helper = std::fabs(n.z) < 0.9 ? Vec3d{0, 0, 1} : Vec3d{1, 0, 0};
    const Vec3d u = normalize(cross(helper, n));
    const Vec3d w = cross(n, u);
    const double h = 0.5 * size_m;
    TriangleMesh m;
    for (const auto& [a, b] :
         {std::pair{-h, -h}, std::pair{h, -h}, std::pair{h, h}, std::pair{-h, h}}) {
        m.vertices.emplace_back(point_m + u * a + w * b);
    }
    m.faces = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

}  // namespace beamtrace
