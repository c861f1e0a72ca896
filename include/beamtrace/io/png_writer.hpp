// PNG images (8-bit RGB and 16-bit grey), written atomically.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>

namespace beamtrace {

/// Writes an 8-bit RGB PNG. `rgb` holds width * height * 3 bytes, row-major, top row first.
/// The file carries a tEXt "Software" chunk naming beamtrace and its version.
/// Throws OutputError (naming the path) on bad dimensions, a size mismatch or any libpng or
/// system error; the final path then keeps its previous content.
void write_png_rgb8(const std::filesystem::path& path, int width, int height,
                    std::span<const std::uint8_t> rgb);

/// write_png_rgb8() of an image still being made: before row y is compressed, `row_ready(y)` is
/// called (rows in order, top first) and returns once row y of `rgb` is final, so the compression
/// of the rows done overlaps the making of the others. The same bytes as write_png_rgb8().
/// `row_ready` must not throw.
void write_png_rgb8_rows(const std::filesystem::path& path, int width, int height,
                         std::span<const std::uint8_t> rgb,
                         const std::function<void(int)>& row_ready);

/// Writes a 16-bit greyscale PNG. `gray` holds width * height samples, row-major, top row first
/// (native integers; the big-endian byte order of PNG is handled here).
/// Writes a range image (`range_m`: width * height metres, row-major, top row first; a pixel
/// without a hit is 0 or not finite) as an 8-bit RGB PNG: jet from the nearest hit (blue) to the
/// farthest (red), misses black, and, when the image is at least 64 pixels wide and has a hit, a
/// colour bar below it that names both ranges. Returns the line for a summary, e.g.
/// "range.png: jet from 5.000 m (blue) to 9.000 m (red); misses black; the colour bar below".
[[nodiscard]] std::string write_range_png(const std::filesystem::path& path,
                                          std::span<const float> range_m, int width, int height);

void write_png_gray16(const std::filesystem::path& path, int width, int height,
                      std::span<const std::uint16_t> gray);

}  // namespace beamtrace
