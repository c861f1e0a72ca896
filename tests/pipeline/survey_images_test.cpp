// labels.png shows the classes in colour; the summary prints the span of range.png's colours,
// and range.png draws it as a colour bar under the image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <string>

#include "beamtrace/io/colormap.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/io/png_reader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(SurveyImages, LabelsInClassColoursAndTheRangeSpanInTheSummary) {
    test::TempDir dir;
    const auto r = test::run_command(
        std::string(BEAMTRACE_CLI_PATH) + " survey " + BEAMTRACE_EXAMPLES_DIR +
        "/surveys/tripod_spheres.yaml --output '" + (dir / "out").string() + "' 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const NpyArray range = read_npy_f32(dir / "out" / "range.npy");
    const RgbImage labels = read_png_rgb8(dir / "out" / "labels.png");
    ASSERT_EQ(labels.rgb.size(), range.data.size() * 3);
    std::map<std::array<std::uint8_t, 3>, std::size_t> colours;
    float lo = 1e30f, hi = 0.0f;
    for (std::size_t i = 0; i < range.data.size(); ++i) {
        const std::array<std::uint8_t, 3> c{labels.rgb[3 * i], labels.rgb[3 * i + 1],
                                            labels.rgb[3 * i + 2]};
        if (range.data[i] > 0.0f) {
            lo = std::min(lo, range.data[i]);
            hi = std::max(hi, range.data[i]);
            ++colours[c];
            EXPECT_TRUE(c == asprs_class_rgb(2) || c == asprs_class_rgb(64)) << i;
        } else {
            ASSERT_EQ(c, (std::array<std::uint8_t, 3>{0, 0, 0})) << i;  // a miss is black
        }
    }
    EXPECT_GT(colours[asprs_class_rgb(2)], 100000u);  // the ground
    EXPECT_GT(colours[asprs_class_rgb(64)], 10u);     // the targets, a colour of their own
    EXPECT_NE(asprs_class_rgb(64), asprs_class_rgb(2));

    const std::size_t at = r.out.find("range.png: jet from ");
    ASSERT_NE(at, std::string::npos) << r.out;
    double nearest = 0.0, farthest = 0.0;
    ASSERT_EQ(std::sscanf(r.out.c_str() + at, "range.png: jet from %lf m (blue) to %lf m (red)",
                          &nearest, &farthest),
              2)
        << r.out;
    EXPECT_NEAR(nearest, lo, 0.0005);
    EXPECT_NEAR(farthest, hi, 0.0005);

    // range.png: the image of range.npy in jet, then a colour bar: a row that runs from jet's
    // blue end to its red end across the image, the rest black but for the labels.
    const RgbImage png = read_png_rgb8(dir / "out" / "range.png");
    const int w = static_cast<int>(range.shape[1]), h = static_cast<int>(range.shape[0]);
    ASSERT_EQ(png.width, w);
    ASSERT_GT(png.height, h + 10);
    const std::vector<std::uint8_t> image = range_image_rgb(range.data, w, h);
    EXPECT_TRUE(std::equal(image.begin(), image.end(), png.rgb.begin()));
    const auto pixel = [&](int x, int y) {
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                   static_cast<std::size_t>(x));
        return std::array<std::uint8_t, 3>{png.rgb[i], png.rgb[i + 1], png.rgb[i + 2]};
    };
    int ramp_row = -1;
    for (int y = h; y < png.height && ramp_row < 0; ++y) {
        ramp_row = pixel(w / 2, y) != std::array<std::uint8_t, 3>{0, 0, 0} ? y : -1;
    }
    ASSERT_GE(ramp_row, h);
    int first = 0, last = w - 1;
    while (pixel(first, ramp_row) == std::array<std::uint8_t, 3>{0, 0, 0}) {
        ++first;
    }
    while (pixel(last, ramp_row) == std::array<std::uint8_t, 3>{0, 0, 0}) {
        --last;
    }
    EXPECT_EQ(pixel(first, ramp_row), jet_color(0.0));
    EXPECT_EQ(pixel(last, ramp_row), jet_color(1.0));
    const int mid = (first + last) / 2;
    EXPECT_EQ(pixel(mid, ramp_row), jet_color(static_cast<double>(mid - first) / (last - first)));
    EXPECT_GT(last - first, w * 9 / 10);
    // White label pixels under the ramp, at both ends.
    std::size_t white_left = 0, white_right = 0;
    for (int y = ramp_row + 1; y < png.height; ++y) {
        for (int x = 0; x < w; ++x) {
            if (pixel(x, y) == std::array<std::uint8_t, 3>{255, 255, 255}) {
                (x < w / 2 ? white_left : white_right) += 1;
            }
        }
    }
    EXPECT_GT(white_left, 20u);
    EXPECT_GT(white_right, 20u);
}

}  // namespace
}  // namespace beamtrace
