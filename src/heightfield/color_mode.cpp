#include "beamtrace/heightfield/color_mode.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "beamtrace/core/name_table.hpp"

namespace beamtrace {

namespace {

constexpr NameTable<ColorMode, 4> kColorModes{"colour mode",
                                              {{{ColorMode::height, "height"},
                                                {ColorMode::rgb, "rgb"},
                                                {ColorMode::intensity, "intensity"},
                                                {ColorMode::classification, "classification"}}}};

}  // namespace

ColorMode parse_color_mode(std::string_view name) {
    return kColorModes.parse(name);
}

std::string_view color_mode_name(ColorMode mode) {
    return kColorModes.to_string(mode);
}

Rgb8 height_ramp(double x) {
    if (!(x > 0.0)) {
        x = 0.0;
    }
    x = std::min(x, 1.0);
    const auto u8 = [](double v) { return static_cast<std::uint8_t>(std::lround(v * 255.0)); };
    if (x < 0.5) {
        const double s = x * 2.0;  // blue -> yellow
        return {u8(s), u8(s), u8(1.0 - s)};
    }
    const double s = (x - 0.5) * 2.0;  // yellow -> red
    return {255, u8(1.0 - s), 0};
}

Rgb8 classification_color(std::uint8_t cls) {
    switch (cls) {
        case 2:  // ground
            return {166, 124, 82};
        case 3:  // low vegetation
            return {144, 238, 144};
        case 4:  // medium vegetation
            return {60, 179, 113};
        case 5:  // high vegetation
            return {34, 110, 34};
        case 6:  // building
            return {220, 90, 60};
        case 7:   // low noise
        case 18:  // high noise
            return {255, 0, 255};
        case 9:  // water
            return {40, 100, 230};
        case 10:  // rail
            return {120, 80, 60};
        case 11:  // road surface
            return {90, 90, 90};
        case 13:  // wire guard
        case 14:  // wire conductor
        case 15:  // transmission tower
            return {255, 220, 0};
        case 17:  // bridge deck
            return {200, 200, 120};
        default:  // never classified, unclassified, others
            return {180, 180, 180};
    }
}

Rgb8 attribute_color(ColorMode mode, std::uint32_t attribute, double intensity_full_scale) {
    switch (mode) {
        case ColorMode::rgb:
            return {static_cast<std::uint8_t>(attribute >> 16),
                    static_cast<std::uint8_t>(attribute >> 8),
                    static_cast<std::uint8_t>(attribute)};
        case ColorMode::intensity: {
            const double v = intensity_full_scale > 0
                                 ? static_cast<double>(attribute) / intensity_full_scale
                                 : 0.0;
            const auto g = static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
            return {g, g, g};
        }
        case ColorMode::classification:
            return classification_color(static_cast<std::uint8_t>(attribute));
        case ColorMode::height:
            break;
    }
    return {255, 255, 255};
}

}  // namespace beamtrace
