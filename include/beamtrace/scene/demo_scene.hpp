// The embedded demo scene: a procedural terrain with three tank-like vehicles and an occluding
// vertical plane, needing no files (the report's test scenes are not public).
#pragma once

#include "beamtrace/scene/scene.hpp"

namespace beamtrace {

struct DemoSceneConfig {
    double terrain_size_m = 200.0;  ///< square terrain centred on the origin
    double cell_size_m = 1.0;       ///< grid spacing (two triangles per cell)
};

/// Parts, in face-ID order: "terrain", "vehicle-1", "vehicle-2", "vehicle-3", "occluder".
/// The occluder is a 4 m x 4 m vertical plane at x = 6 m in front of vehicle 1 (at the origin),
/// like the report's occlusion example.
[[nodiscard]] Scene make_demo_scene(const DemoSceneConfig& config = {});

/// Terrain height of the demo scene at (x, y), metres.
[[nodiscard]] double demo_terrain_height(double x_m, double y_m);

}  // namespace beamtrace
