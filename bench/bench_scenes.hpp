// Scenes and rays shared by the benchmarks: the 1 M-triangle terrain and its nadir pinhole.
#pragma once

#include <numbers>

#include "beamtrace/geometry/triangle_mesh.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/sensor/image_sensor.hpp"

namespace beamtrace::bench {

/// 708 x 708 cells, 2 triangles each: 1 002 528 triangles over 708 m x 708 m.
inline const TriangleMesh& terrain_1m() {
    static const TriangleMesh mesh = [] {
        constexpr int n = 708;
        TriangleMesh m;
        for (int j = 0; j <= n; ++j) {
            for (int i = 0; i <= n; ++i) {
                const double x = i - n / 2.0, y = j - n / 2.0;
                m.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y),
                                        static_cast<float>(demo_terrain_height(x, y)));
            }
        }
        auto idx = [](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                m.faces.push_back({idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)});
                m.faces.push_back({idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)});
            }
        }
        return m;
    }();
    return mesh;
}

/// A 512x512 nadir pinhole 400 m above the terrain, 60 degree FOV: every ray hits.
inline const RayBatch& nadir_rays() {
    static const RayBatch rays = [] {
        ImageSensorConfig c;
        c.position_m = {0.0, 0.0, 400.0};
        c.orientation = {0.0, -std::numbers::pi / 2, 0.0};
        c.width = 512;
        c.height = 512;
        c.hfov_rad = std::numbers::pi / 3;
        c.vfov_rad = std::numbers::pi / 3;
        return cast_rays_pinhole(c);
    }();
    return rays;
}

}  // namespace beamtrace::bench
