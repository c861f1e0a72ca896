#include "beamtrace/io/colormap.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

namespace beamtrace {

namespace {

/// A bright colour of hue h in [0, 1) (saturation 0.7, value 0.95).
std::array<std::uint8_t, 3> hue_rgb(double h) {
    const double v = 0.95, s = 0.7;
    const double x = h * 6.0;
    const int sector = static_cast<int>(x) % 6;
    const double f = x - std::floor(x);
    const double p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
    const double rgb[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
    const auto u8 = [](double c) { return static_cast<std::uint8_t>(std::lround(c * 255.0)); };
    return {u8(rgb[sector][0]), u8(rgb[sector][1]), u8(rgb[sector][2])};
}

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

std::optional<std::pair<float, float>> valid_range_span(std::span<const float> range_m) {
    float nearest = std::numeric_limits<float>::infinity();
    float farthest = -std::numeric_limits<float>::infinity();
    for (const float r : range_m) {
        if (is_hit(r)) {
            nearest = std::min(nearest, r);
            farthest = std::max(farthest, r);
        }
    }
    if (!(nearest <= farthest)) {
        return std::nullopt;
    }
    return std::pair{nearest, farthest};
}

std::vector<std::uint8_t> range_image_rgb(std::span<const float> range_m, int width, int height) {
    if (width < 0 || height < 0 || range_m.size() != std::size_t(width) * std::size_t(height)) {
        throw std::invalid_argument("range_image_rgb: " + std::to_string(width) + "x" +
                                    std::to_string(height) + " image but " +
                                    std::to_string(range_m.size()) + " ranges");
    }
    const auto span = valid_range_span(range_m);
    const float nearest = span ? span->first : 0.0f;
    const float farthest = span ? span->second : 0.0f;
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

std::array<std::uint8_t, 3> asprs_class_rgb(std::uint8_t cls) {
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
        case 0:  // never classified
        case 1:  // unclassified
            return {180, 180, 180};
        default:  // reserved and user classes: a hue of their own (golden-ratio steps)
            return hue_rgb(std::fmod(static_cast<double>(cls) * 0.6180339887498949, 1.0));
    }
}

std::vector<std::uint8_t> class_image_rgb(std::span<const std::uint16_t> classes,
                                          std::span<const float> range_m, int width, int height) {
    const auto n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    if (classes.size() != n || range_m.size() != n) {
        throw std::invalid_argument("class_image_rgb: " + std::to_string(width) + "x" +
                                    std::to_string(height) + " image with " +
                                    std::to_string(classes.size()) + " classes and " +
                                    std::to_string(range_m.size()) + " ranges");
    }
    std::vector<std::uint8_t> rgb(3 * n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        if (range_m[i] > 0.0f && std::isfinite(range_m[i])) {
            const auto c = asprs_class_rgb(
                static_cast<std::uint8_t>(std::min<std::uint16_t>(classes[i], 255)));
            std::copy(c.begin(), c.end(), rgb.begin() + static_cast<std::ptrdiff_t>(3 * i));
        }
    }
    return rgb;
}

}  // namespace beamtrace
