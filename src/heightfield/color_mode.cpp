#include "beamtrace/heightfield/color_mode.hpp"

#include "beamtrace/io/colormap.hpp"

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
    const auto c = asprs_class_rgb(cls);
    return {c[0], c[1], c[2]};
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
