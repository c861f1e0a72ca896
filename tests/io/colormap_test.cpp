#include "beamtrace/io/colormap.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace beamtrace {
namespace {

using Rgb = std::array<std::uint8_t, 3>;

/// HSV hue in degrees, [0, 360).
double hue_deg(const Rgb& c) {
    const double r = c[0] / 255.0;
    const double g = c[1] / 255.0;
    const double b = c[2] / 255.0;
    const double max = std::max({r, g, b});
    const double min = std::min({r, g, b});
    const double delta = max - min;
    if (delta == 0.0) {
        return 0.0;
    }
    double h = 0.0;
    if (max == r) {
        h = std::fmod((g - b) / delta, 6.0);
    } else if (max == g) {
        h = (b - r) / delta + 2.0;
    } else {
        h = (r - g) / delta + 4.0;
    }
    h *= 60.0;
    return h < 0.0 ? h + 360.0 : h;
}

void expect_near_rgb(const Rgb& actual, const Rgb& expected, int tolerance) {
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_NEAR(actual[k], expected[k], tolerance)
            << "channel " << k << " of (" << int(actual[0]) << ", " << int(actual[1]) << ", "
            << int(actual[2]) << ")";
    }
}

TEST(Colormap, JetEndpointsAreDarkBlueAndDarkRed) {
    // Matlab's jet(64) starts at (0, 0, 143) and ends at (128, 0, 0).
    expect_near_rgb(jet_color(0.0), {0, 0, 143}, 16);
    expect_near_rgb(jet_color(1.0), {128, 0, 0}, 16);
    EXPECT_EQ(jet_color(0.0), (Rgb{0, 0, 128}));
    EXPECT_EQ(jet_color(1.0), (Rgb{128, 0, 0}));
}

TEST(Colormap, JetPassesThroughBlueCyanYellowRed) {
    EXPECT_EQ(jet_color(0.125), (Rgb{0, 0, 255}));
    EXPECT_EQ(jet_color(0.375), (Rgb{0, 255, 255}));
    EXPECT_EQ(jet_color(0.5), (Rgb{128, 255, 128}));
    EXPECT_EQ(jet_color(0.625), (Rgb{255, 255, 0}));
    EXPECT_EQ(jet_color(0.875), (Rgb{255, 0, 0}));
}

TEST(Colormap, JetIsClamped) {
    EXPECT_EQ(jet_color(-3.0), jet_color(0.0));
    EXPECT_EQ(jet_color(7.0), jet_color(1.0));
    EXPECT_EQ(jet_color(-std::numeric_limits<double>::infinity()), jet_color(0.0));
    EXPECT_EQ(jet_color(std::numeric_limits<double>::infinity()), jet_color(1.0));
    EXPECT_EQ(jet_color(std::numeric_limits<double>::quiet_NaN()), jet_color(0.0));
}

TEST(Colormap, JetHueFallsMonotonicallyFromBlueToRed) {
    double previous = hue_deg(jet_color(0.0));
    EXPECT_NEAR(previous, 240.0, 1e-9);
    for (int i = 1; i <= 1000; ++i) {
        const double hue = hue_deg(jet_color(i / 1000.0));
        EXPECT_LE(hue, previous + 1e-9) << "x = " << i / 1000.0;
        previous = hue;
    }
    EXPECT_NEAR(previous, 0.0, 1e-9);
}

TEST(Colormap, RangeImageMapsNearToBlueFarToRedAndMissesToBlack) {
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<float> range_m = {10.0f, 0.0f, 30.0f, 20.0f, inf, nan, -1.0f, 15.0f};
    const std::vector<std::uint8_t> rgb = range_image_rgb(range_m, 4, 2);
    ASSERT_EQ(rgb.size(), range_m.size() * 3);
    const auto pixel = [&](std::size_t i) {
        return Rgb{rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]};
    };
    EXPECT_EQ(pixel(0), jet_color(0.0));
    EXPECT_EQ(pixel(2), jet_color(1.0));
    EXPECT_EQ(pixel(3), jet_color(0.5));
    EXPECT_EQ(pixel(7), jet_color(0.25));
    for (const std::size_t miss : {1u, 4u, 5u, 6u}) {
        EXPECT_EQ(pixel(miss), (Rgb{0, 0, 0})) << "pixel " << miss;
    }
}

TEST(Colormap, RangeImageWithOneDistinctRangeUsesTheMiddle) {
    const std::vector<float> range_m = {5.0f, 0.0f, 5.0f, 5.0f};
    const std::vector<std::uint8_t> rgb = range_image_rgb(range_m, 2, 2);
    EXPECT_EQ((Rgb{rgb[0], rgb[1], rgb[2]}), jet_color(0.5));
    EXPECT_EQ((Rgb{rgb[3], rgb[4], rgb[5]}), (Rgb{0, 0, 0}));
}

TEST(Colormap, RangeImageOfOnlyMissesIsBlack) {
    const std::vector<float> range_m(6, 0.0f);
    const std::vector<std::uint8_t> rgb = range_image_rgb(range_m, 3, 2);
    EXPECT_TRUE(std::all_of(rgb.begin(), rgb.end(), [](std::uint8_t c) { return c == 0; }));
}

TEST(Colormap, RangeImageChecksItsSize) {
    const std::vector<float> range_m(5, 1.0f);
    EXPECT_THROW(static_cast<void>(range_image_rgb(range_m, 2, 2)), std::invalid_argument);
    EXPECT_THROW(static_cast<void>(range_image_rgb(range_m, -5, -1)), std::invalid_argument);
}

}  // namespace
}  // namespace beamtrace
