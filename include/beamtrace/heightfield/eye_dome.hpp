// Eye-dome lighting (Boucheny 2009): a screen-space shading from the depth image alone that
// outlines depth edges, so that columns, crowns and walls of a point cloud stand apart without
// normals.
#pragma once

#include "beamtrace/heightfield/view_renderer.hpp"

namespace beamtrace {

/// Pixels from which eye_dome_shade() takes its neighbours (8 of them, at this radius).
inline constexpr int kEyeDomeRadius = 2;

/// The factor eye_dome_shade() multiplies a pixel's colour by: exp(-100 * strength * r), with r
/// the mean over its 8 neighbours at kEyeDomeRadius pixels of max(0, log2 d - log2 d_n)
/// (neighbours that are nearer darken it; misses and the frame's outside count as far).
[[nodiscard]] double eye_dome_shade(const ViewImage& image, int x, int y, double strength);

/// Multiplies every hit pixel's colour of `image` by eye_dome_shade() (from the depths as
/// rendered, so the result does not depend on the threads of `pool`). strength <= 0: nothing.
void apply_eye_dome(ViewImage& image, double strength, ThreadPool& pool);

}  // namespace beamtrace
