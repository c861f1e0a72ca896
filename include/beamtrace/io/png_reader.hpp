// Reading PNG images back as 8-bit RGB (for screenshots and image comparisons).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace beamtrace {

struct RgbImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  ///< width * height * 3, row-major, top row first
};

/// Reads any PNG (grey, palette, alpha, 16-bit: converted by libpng; alpha is dropped over
/// black) as 8-bit RGB. Throws InputError naming the file when it cannot be read or decoded.
[[nodiscard]] RgbImage read_png_rgb8(const std::filesystem::path& path);

}  // namespace beamtrace
