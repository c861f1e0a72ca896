// Where most of the points lie: the box that the default `view` camera frames, so that a few
// far points (a spinning scanner's long-range rings, outliers) do not shrink the data to a
// corner of the image.
#pragma once

#include <cstddef>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/heightfield/las_sources.hpp"

namespace beamtrace {

/// Share of the points left out on each side of each horizontal axis by points_box().
inline constexpr double kFramingTrim = 0.02;
/// points_box() keeps the headers' box unless the quantile box covers less than this share of
/// its area (uniform data stay framed whole).
inline constexpr double kFramingShrink = 0.5;
/// Margin added on each side of a quantile box, as a share of its size.
inline constexpr double kFramingMargin = 0.1;

struct PointsBox {
    Vec3d lo, hi;             ///< x, y: the quantiles; z: the headers' range
    std::size_t samples = 0;  ///< points read for it (0: the headers' box)
};

/// The box from the `trim` to the 1 - `trim` quantile in x and in y of about `samples` points
/// read evenly across the files (in proportion to their point counts), widened by
/// kFramingMargin, with the headers' z range; the headers' box where that box is not smaller
/// than kFramingShrink of it, or no point can be read. LAS records are read one by one at evenly
/// spaced indices; LAZ in runs of 4096 points decoded at up to 16 evenly spaced places.
[[nodiscard]] PointsBox points_box(const LasSourceSet& sources, double trim = kFramingTrim,
                                   std::size_t samples = 8192);

}  // namespace beamtrace
