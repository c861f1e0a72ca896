// Colour maps for range images.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace beamtrace {

/// Matlab's "jet" map as a continuous function: x = 0 is dark blue (0, 0, 128), then blue, cyan,
/// yellow, red, and x = 1 is dark red (128, 0, 0). x is clamped to [0, 1]; NaN maps like 0.
[[nodiscard]] std::array<std::uint8_t, 3> jet_color(double x);

/// Colours a range image (width * height ranges in metres, row-major, top row first) with jet,
/// from the nearest valid range (blue) to the farthest (red). Misses — 0, negative or non-finite
/// ranges — are black. When every hit has the same range, hits get the middle of the map.
/// Returns width * height * 3 bytes for write_png_rgb8. Throws std::invalid_argument when the
/// size of `range_m` does not match the dimensions.
[[nodiscard]] std::vector<std::uint8_t> range_image_rgb(std::span<const float> range_m, int width,
                                                        int height);

}  // namespace beamtrace
