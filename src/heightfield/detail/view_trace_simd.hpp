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

}  // namespace beamtrace::detail
