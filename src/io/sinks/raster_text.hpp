// Pixels and text (the 5 x 7 font of preview_font.hpp) drawn into RGB8 images: the scale bar of
// preview.png and the colour bar of range.png.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace beamtrace::detail {

using Rgb8Pixel = std::array<std::uint8_t, 3>;

/// Sets pixel (x, y) of the w x h image `rgb` to `c`; nothing outside the image.
void put_pixel(std::vector<std::uint8_t>& rgb, int w, int h, int x, int y, Rgb8Pixel c);

/// Draws `text` with its top-left at (x, y), each font pixel `s` x `s`, in `c`.
void draw_text(std::vector<std::uint8_t>& rgb, int w, int h, int x, int y, int s,
               const std::string& text, Rgb8Pixel c);

/// The width in pixels of `text` drawn at scale `s`.
[[nodiscard]] int text_width(const std::string& text, int s);

}  // namespace beamtrace::detail
