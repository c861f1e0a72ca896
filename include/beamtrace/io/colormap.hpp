// Colour maps for range images.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace beamtrace {

/// Matlab's "jet" map as a continuous function: x = 0 is dark blue (0, 0, 128), then blue, cyan,
/// yellow, red, and x = 1 is dark red (128, 0, 0). x is clamped to [0, 1]; NaN maps like 0.
[[nodiscard]] std::array<std::uint8_t, 3> jet_color(double x);

/// The nearest and farthest valid range (> 0 and finite) of a range image: the ends of the
/// colours of range_image_rgb; nullopt without any.
[[nodiscard]] std::optional<std::pair<float, float>> valid_range_span(
    std::span<const float> range_m);

/// Colours a range image (width * height ranges in metres, row-major, top row first) with jet,
/// from the nearest valid range (blue) to the farthest (red). Misses — 0, negative or non-finite
/// ranges — are black. When every hit has the same range, hits get the middle of the map.
/// Returns width * height * 3 bytes for write_png_rgb8. Throws std::invalid_argument when the
/// size of `range_m` does not match the dimensions.
[[nodiscard]] std::vector<std::uint8_t> range_image_rgb(std::span<const float> range_m, int width,
                                                        int height);

/// The colour of an ASPRS LAS class (2 ground brown, 3-5 vegetation greens, 6 building red,
/// 9 water blue, 7/18 noise magenta, 10 rail, 11 road grey, 13-15 wires yellow, 17 bridge);
/// light grey for 0 and 1; every other class (8, 12, 16, 19-255, user classes such as 64) a
/// bright hue of its own. Shared by `view --color classification` and labels.png.
[[nodiscard]] std::array<std::uint8_t, 3> asprs_class_rgb(std::uint8_t cls);

/// Colours a class image (width * height classes, row-major) with asprs_class_rgb where the
/// pixel holds a hit (range > 0 and finite), black elsewhere; width * height * 3 bytes.
/// std::invalid_argument when the sizes do not match.
[[nodiscard]] std::vector<std::uint8_t> class_image_rgb(std::span<const std::uint16_t> classes,
                                                        std::span<const float> range_m, int width,
                                                        int height);

}  // namespace beamtrace
