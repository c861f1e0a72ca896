// How the height field is coloured, and the 32-bit per-cell attribute each mode stores.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace beamtrace {

using Rgb8 = std::array<std::uint8_t, 3>;

/// The colour source of a view.
enum class ColorMode {
    height,          ///< the thesis's ramp blue -> yellow -> red over the resident height range;
                     ///< stores no attribute (4 bytes per cell less)
    rgb,             ///< the LAS RGB of the highest point of the cell (formats 2, 3, 5, 7, 8, 10)
    intensity,       ///< grey from the LAS intensity of the highest point
    classification,  ///< ASPRS class colours of the highest point
};

/// Parses "height", "rgb", "intensity" or "classification"; throws ConfigError otherwise.
[[nodiscard]] ColorMode parse_color_mode(std::string_view name);
[[nodiscard]] std::string_view color_mode_name(ColorMode mode);
/// Whether the mode needs a per-cell attribute.
[[nodiscard]] constexpr bool color_mode_has_attribute(ColorMode mode) {
    return mode != ColorMode::height;
}

/// The height ramp: x = 0 blue (0, 0, 255), x = 0.5 yellow (255, 255, 0), x = 1 red (255, 0, 0);
/// x is clamped to [0, 1], NaN maps like 0.
[[nodiscard]] Rgb8 height_ramp(double x);

/// Colours of the ASPRS standard classes (ground brown, vegetation greens, buildings red-orange,
/// water blue, ...); unknown classes are grey.
[[nodiscard]] Rgb8 classification_color(std::uint8_t cls);

/// Attribute encodings: rgb packs 8-bit red << 16 | green << 8 | blue; intensity holds the raw
/// 16-bit value; classification the class.
[[nodiscard]] constexpr std::uint32_t pack_rgb8(std::uint32_t r, std::uint32_t g, std::uint32_t b) {
    return (r << 16) | (g << 8) | b;
}

/// Colour of a cell from its attribute. `intensity_full_scale` is the intensity drawn white.
[[nodiscard]] Rgb8 attribute_color(ColorMode mode, std::uint32_t attribute,
                                   double intensity_full_scale);

}  // namespace beamtrace
