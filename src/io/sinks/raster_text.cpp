#include "io/sinks/raster_text.hpp"

#include <algorithm>

#include "io/sinks/preview_font.hpp"

namespace beamtrace::detail {

void put_pixel(std::vector<std::uint8_t>& rgb, int w, int h, int x, int y, Rgb8Pixel c) {
    if (x >= 0 && y >= 0 && x < w && y < h) {
        const auto i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                            static_cast<std::size_t>(x));
        std::copy(c.begin(), c.end(), rgb.begin() + static_cast<std::ptrdiff_t>(i));
    }
}

void draw_text(std::vector<std::uint8_t>& rgb, int w, int h, int x, int y, int s,
               const std::string& text, Rgb8Pixel c) {
    for (std::size_t k = 0; k < text.size(); ++k) {
        const auto rows = glyph_rows(text[k]);
        const int gx = x + static_cast<int>(k) * (kGlyphWidth + 1) * s;
        for (int row = 0; row < kGlyphHeight; ++row) {
            for (int col = 0; col < kGlyphWidth; ++col) {
                if ((rows[static_cast<std::size_t>(row)] >> (kGlyphWidth - 1 - col)) & 1) {
                    for (int i = 0; i < s * s; ++i) {
                        put_pixel(rgb, w, h, gx + col * s + i % s, y + row * s + i / s, c);
                    }
                }
            }
        }
    }
}

int text_width(const std::string& text, int s) {
    return text.empty() ? 0 : (static_cast<int>(text.size()) * (kGlyphWidth + 1) - 1) * s;
}

}  // namespace beamtrace::detail
