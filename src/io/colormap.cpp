#include "beamtrace/io/colormap.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

namespace beamtrace {

namespace {

/// One channel of jet: a trapezoid of height 1 centred at `centre`, 0.75 wide at the top.
std::uint8_t jet_channel(double x, double centre) {
    const double c = std::clamp(1.5 - std::abs(4.0 * (x - centre)), 0.0, 1.0);
    return static_cast<std::uint8_t>(std::lround(c * 255.0));
}

[[nodiscard]] bool is_hit(float range_m) {
    return std::isfinite(range_m) && range_m > 0.0f;
}

}  // namespace

std::array<std::uint8_t, 3> jet_color(double x) {
    x = std::isnan(x) ? 0.0 : std::clamp(x, 0.0, 1.0);
    return {jet_channel(x, 0.75), jet_channel(x, 0.5), jet_channel(x, 0.25)};
}

std::vector<std::uint8_t> range_image_rgb(std::span<const float> range_m, int width, int height) {
    if (width < 0 || height < 0 || range_m.size() != std::size_t(width) * std::size_t(height)) {
        throw std::invalid_argument("range_image_rgb: " + std::to_string(width) + "x" +
                                    std::to_string(height) + " image but " +
                                    std::to_string(range_m.size()) + " ranges");
    }
    float nearest = std::numeric_limits<float>::infinity();
    float farthest = -std::numeric_limits<float>::infinity();
    for (const float r : range_m) {
        if (is_hit(r)) {
            nearest = std::min(nearest, r);
            farthest = std::max(farthest, r);
        }
    }
    const double spread_m = double(farthest) - double(nearest);
    std::vector<std::uint8_t> rgb(range_m.size() * 3, 0);
    for (std::size_t i = 0; i < range_m.size(); ++i) {
        if (!is_hit(range_m[i])) {
            continue;
        }
        const double x = spread_m > 0.0 ? (double(range_m[i]) - double(nearest)) / spread_m : 0.5;
        const auto colour = jet_color(x);
        std::copy(colour.begin(), colour.end(), rgb.begin() + std::ptrdiff_t(3 * i));
    }
    return rgb;
}

}  // namespace beamtrace
