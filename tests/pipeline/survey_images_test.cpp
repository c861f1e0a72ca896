// labels.png shows the classes in colour; the summary prints the span of range.png's colours.
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
}

}  // namespace
}  // namespace beamtrace
