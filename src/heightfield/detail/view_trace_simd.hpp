// The hierarchical view traversal several rays at a time in SIMD lanes (AVX2: 4, AVX-512: 8),
// for CPUs that have them.
#pragma once

#include <cstddef>
#include <cstdint>

#include "grid_ray.hpp"
#include "level_table.hpp"

namespace beamtrace::detail {

/// Lanes of the widest kernel this CPU runs: 8 (x86-64 with AVX-512 F, DQ and CD), 4 (AVX2) or
/// 1 (none: trace one ray at a time).
[[nodiscard]] int widest_lanes();

/// Traces rays[0, count) through `table` (which must have no height stacks) with the walk and
/// the arithmetic of the scalar traversal (start at the sections' coarsest level, descend on a
/// potential hit, step and climb otherwise, into the pyramid only over empty cells), `lanes`
/// rays (4 or 8, at most widest_lanes()) in the lanes of SIMD registers, a lane taking the next
/// ray as soon as its ray ends. Sets found[i] (1: hit) and, for hits, hits[i]: the same cell,
/// distances and height as the scalar traversal, bit for bit. Returns the lanes of the kernel
/// that ran (8: AVX-512, 4: AVX2), which the renderer reports in ViewImage::kernel_lanes.
[[nodiscard]] int trace_rays_lanes(int lanes, const LevelTable& table, const GridRay* rays,
                                   std::size_t count, GridHit* hits, std::uint8_t* found);

/// What the pixel directions of a frame depend on: CameraRays' forward, right and up vectors
/// and RaySetup::per_cell().
struct DirectionFrame {
    double fx = 0, fy = 0, fz = 0, rx = 0, ry = 0, rz = 0, ux = 0, uy = 0, uz = 0;
    double per_cell = 1;
};

/// The rays of up to kRowDirections pixels of one row, as RaySetup::operator() sets them up.
inline constexpr int kRowDirections = 8;
struct alignas(64) RowDirections {
    double dx[kRowDirections], dy[kRowDirections], dz[kRowDirections];
    double inv_dx[kRowDirections], inv_dy[kRowDirections], inv_dz[kRowDirections];
    /// RaySetup::clip's span and start cell (gx, gy as doubles, exact) of the rays in `enter`.
    double t_min[kRowDirections], t_max[kRowDirections], gx[kRowDirections], gy[kRowDirections];
    int enter = 0;  ///< bit i: ray i enters the loaded heights (RaySetup::clip is true)
};

/// For pixels at image-plane coordinates (u[i], v), i < count <= kRowDirections: dx, dy and dz
/// of the ray along CameraRays::direction_at(u[i], v) in cells (dir.x * per_cell, dir.y *
/// per_cell, dir.z), inv_dx and inv_dy (1 / d, kInf for 0) and inv_dz = 1 / dz: the values
/// RaySetup::operator() works out; then RaySetup::clip's with `clip` (RaySetup::clip_frame()):
/// which rays enter (out.enter), their t_min, t_max, gx and gy. The same IEEE operations in the
/// same order (none fused) and the same choices on ties and signed zeros, so every value is the
/// scalar one bit for bit; `lanes` (4 or 8, at most widest_lanes()) rays at a time.
void ray_setup_lanes(int lanes, const DirectionFrame& frame, const ClipFrame& clip, const double* u,
                     double v, int count, RowDirections& out);

}  // namespace beamtrace::detail
