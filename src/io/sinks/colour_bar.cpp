#include "io/sinks/colour_bar.hpp"

#include <cstdio>
#include <string>

#include "beamtrace/io/colormap.hpp"
#include "io/sinks/preview_font.hpp"
#include "io/sinks/raster_text.hpp"

namespace beamtrace::detail {
namespace {

int scale(int width) {
    return width >= 400 ? 2 : 1;
}

std::string range_text(float m) {
    char text[32];
    if (m >= 1000.0f) {
        std::snprintf(text, sizeof text, "%.4g km", static_cast<double>(m) / 1000.0);
    } else {
        std::snprintf(text, sizeof text, "%.4g m", static_cast<double>(m));
    }
    return text;
}

}  // namespace

int colour_bar_rows(int width) {
    return width < kColourBarMinWidth ? 0 : (4 + 6 + 3 + kGlyphHeight + 3) * scale(width);
}

void append_colour_bar(std::vector<std::uint8_t>& rgb, int width, float near_m, float far_m) {
    const int rows = colour_bar_rows(width);
    if (rows == 0) {
        return;
    }
    const int s = scale(width);
    std::vector<std::uint8_t> bar(3 * static_cast<std::size_t>(width) * rows, 0);
    const int x0 = 4 * s, x1 = width - 1 - 4 * s;
    for (int x = x0; x <= x1; ++x) {
        const auto c = jet_color(static_cast<double>(x - x0) / static_cast<double>(x1 - x0));
        for (int y = 4 * s; y < 10 * s; ++y) {
            put_pixel(bar, width, rows, x, y, c);
        }
    }
    const std::string lo = range_text(near_m), hi = range_text(far_m);
    const int ty = 13 * s;
    const Rgb8Pixel white = {255, 255, 255};
    draw_text(bar, width, rows, x0, ty, s, lo, white);
    if (text_width(lo, s) + text_width(hi, s) + 4 * s <= x1 - x0) {
        draw_text(bar, width, rows, x1 + 1 - text_width(hi, s), ty, s, hi, white);
    }
    rgb.insert(rgb.end(), bar.begin(), bar.end());
}

}  // namespace beamtrace::detail
