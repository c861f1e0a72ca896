// The hierarchical view traversal four rays at a time in AVX2 lanes, for CPUs that have it.
#pragma once

#include <cstddef>
#include <cstdint>

#include "grid_ray.hpp"
#include "level_table.hpp"

namespace beamtrace::detail {

/// Whether this CPU runs trace_rays_avx2 (x86-64 with AVX2; false elsewhere).
[[nodiscard]] bool avx2_available();

/// Traces rays[0, count) through `table` (which must have no height stacks) with the walk and
/// the arithmetic of the scalar traversal (start at the sections' coarsest level, descend on a
/// potential hit, step and climb otherwise, into the pyramid only over empty cells), four rays
/// in the lanes of AVX2 registers, a lane taking the next ray as soon as its ray ends. Sets
/// found[i] (1: hit) and, for hits, hits[i]: the same cell, distances and height as the scalar
/// traversal, bit for bit. Call only where avx2_available().
void trace_rays_avx2(const LevelTable& table, const GridRay* rays, std::size_t count, GridHit* hits,
                     std::uint8_t* found);

}  // namespace beamtrace::detail
