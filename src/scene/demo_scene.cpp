#include "beamtrace/scene/demo_scene.hpp"

#include <cmath>
#include <numbers>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

/// An axis-aligned box as 12 outward-facing triangles.
TriangleMesh make_box(const Vec3d& lo, const Vec3d& hi) {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i) {
        m.vertices.emplace_back(static_cast<float>((i & 1) ? hi.x : lo.x),
                                static_cast<float>((i & 2) ? hi.y : lo.y),
                                static_cast<float>((i & 4) ? hi.z : lo.z));
    }
    // Corner i has x from bit 0, y from bit 1, z from bit 2. Faces are CCW seen from outside.
    m.faces = {{0, 2, 1}, {1, 2, 3},   // bottom (z = lo)
               {4, 5, 6}, {5, 7, 6},   // top
               {0, 1, 4}, {1, 5, 4},   // y = lo
               {2, 6, 3}, {3, 6, 7},   // y = hi
               {0, 4, 2}, {2, 4, 6},   // x = lo
               {1, 3, 5}, {3, 7, 5}};  // x = hi
    return m;
}

TriangleMesh make_vehicle(double cx, double cy, double heading_rad) {
    const double ground = demo_terrain_height(cx, cy);
    TriangleMesh v;
    v.append(make_box({-3.5, -1.75, 0.3}, {3.5, 1.75, 1.8}));  // hull
    v.append(make_box({-1.8, -1.2, 1.8}, {1.2, 1.2, 2.6}));    // turret
    v.append(make_box({1.2, -0.12, 2.05}, {5.6, 0.12, 2.3}));  // barrel
    v.append(make_box({-3.3, -1.9, 0.0}, {3.3, -1.2, 0.9}));   // tracks
    v.append(make_box({-3.3, 1.2, 0.0}, {3.3, 1.9, 0.9}));
    const double c = std::cos(heading_rad), s = std::sin(heading_rad);
    for (auto& p : v.vertices) {
        const double x = p.x, y = p.y;
        p = Vec3f(static_cast<float>(cx + c * x - s * y), static_cast<float>(cy + s * x + c * y),
                  static_cast<float>(ground + p.z));
    }
    return v;
}

}  // namespace

double demo_terrain_height(double x_m, double y_m) {
    return 2.5 * std::sin(x_m / 23.0) * std::cos(y_m / 17.0) +
           0.6 * std::sin(x_m / 7.0 + y_m / 9.0) + 0.002 * (x_m * x_m + y_m * y_m) / 10.0;
}

Scene make_demo_scene(const DemoSceneConfig& config) {
    if (!(config.cell_size_m > 0.0) || !(config.terrain_size_m >= config.cell_size_m)) {
        throw ConfigError("demo scene: need 0 < cell_size_m <= terrain_size_m");
    }
    const int n = static_cast<int>(std::lround(config.terrain_size_m / config.cell_size_m));
    if (n > 20000) {
        throw ConfigError("demo scene: more than 20000 x 20000 cells");
    }
    const double half = 0.5 * config.terrain_size_m;
    TriangleMesh terrain;
    terrain.vertices.reserve(static_cast<std::size_t>(n + 1) * static_cast<std::size_t>(n + 1));
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const double x = -half + config.cell_size_m * i;
            const double y = -half + config.cell_size_m * j;
            terrain.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y),
                                          static_cast<float>(demo_terrain_height(x, y)));
        }
    }
    const auto idx = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    terrain.faces.reserve(2 * static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            terrain.faces.push_back({idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)});
            terrain.faces.push_back({idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)});
        }
    }
    Scene scene;
    scene.add_part("terrain", terrain);
    scene.add_part("vehicle-1", make_vehicle(0.0, 0.0, 0.0));
    scene.add_part("vehicle-2", make_vehicle(-25.0, 18.0, 0.6));
    scene.add_part("vehicle-3", make_vehicle(-30.0, -20.0, -0.4));

    // Occluding plane: x = 6, y in [-5, -1], z from 0.5 m below the ground to 4 m above.
    const float g = static_cast<float>(demo_terrain_height(6.0, -3.0));
    TriangleMesh plane;
    plane.vertices = {{6.0f, -5.0f, g - 0.5f},
                      {6.0f, -1.0f, g - 0.5f},
                      {6.0f, -1.0f, g + 3.5f},
                      {6.0f, -5.0f, g + 3.5f}};
    plane.faces = {{0, 2, 3}, {0, 1, 2}};
    scene.add_part("occluder", plane);
    return scene;
}

}  // namespace beamtrace
