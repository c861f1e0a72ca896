// The colour bar under range.png: the jet ramp from the nearest to the farthest range, labelled
// with both in metres (or km), on black.
#pragma once

#include <cstdint>
#include <vector>

namespace beamtrace::detail {

/// Images narrower than this get no colour bar.
inline constexpr int kColourBarMinWidth = 64;

/// The rows the bar adds under a `width`-pixel image (0 below kColourBarMinWidth).
[[nodiscard]] int colour_bar_rows(int width);

/// Appends the bar's colour_bar_rows(width) rows to the width-wide RGB8 image `rgb`.
void append_colour_bar(std::vector<std::uint8_t>& rgb, int width, float near_m, float far_m);

}  // namespace beamtrace::detail
