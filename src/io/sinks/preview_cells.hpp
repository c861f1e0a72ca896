// preview.png's binning: the pixel of each point of a block, in AVX2 lanes where the CPU has them
// (the same pixels and heights as the scalar code on every CPU).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "beamtrace/io/point_sink.hpp"

namespace beamtrace::detail {

/// The preview's raster: `width` x `height` pixels of `cell_m`, rows from `north` down, columns
/// from `west` on; per_cell = 1 / cell_m.
struct PreviewGrid {
    double west = 0.0, north = 0.0, cell_m = 1.0, per_cell = 1.0;
    int width = 1, height = 1;
};

/// The points of `points` that fall on the grid, in order: the n-th one's pixel (row * width +
/// column, each cells_floor() of its distance from the west or north edge) into pixel[n], its
/// height as a float (-0 as +0) into height[n]. Returns n; pixel and height hold points.size().
std::size_t preview_cells(std::span<const BlockPoint> points, const PreviewGrid& grid,
                          std::uint32_t* pixel, float* height);

/// The same, always by the scalar code (for tests of the lanes).
std::size_t preview_cells_scalar(std::span<const BlockPoint> points, const PreviewGrid& grid,
                                 std::uint32_t* pixel, float* height);

/// The hits of one row of heights (pixels other than `empty`, which is below every height): the
/// first and last one's column (-1 without hits) and the lowest and highest height.
struct RowHits {
    int first = -1, last = -1;
    float lo = 0.0f, hi = 0.0f;
};

/// The hits of row[0, width), in AVX2 lanes where the CPU has them.
RowHits row_hits(const float* row, int width, float empty);

/// The same, always by the scalar code (for tests of the lanes).
RowHits row_hits_scalar(const float* row, int width, float empty);

}  // namespace beamtrace::detail
