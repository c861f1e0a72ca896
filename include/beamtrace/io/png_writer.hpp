// PNG images (8-bit RGB and 16-bit grey), written atomically.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>

namespace beamtrace {

/// Writes an 8-bit RGB PNG. `rgb` holds width * height * 3 bytes, row-major, top row first.
/// The file carries a tEXt "Software" chunk naming beamtrace and its version.
/// Throws OutputError (naming the path) on bad dimensions, a size mismatch or any libpng or
/// system error; the final path then keeps its previous content.
void write_png_rgb8(const std::filesystem::path& path, int width, int height,
                    std::span<const std::uint8_t> rgb);

/// Writes a 16-bit greyscale PNG. `gray` holds width * height samples, row-major, top row first
/// (native integers; the big-endian byte order of PNG is handled here).
void write_png_gray16(const std::filesystem::path& path, int width, int height,
                      std::span<const std::uint16_t> gray);

}  // namespace beamtrace
