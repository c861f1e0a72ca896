// `beamtrace view FILE --output v.png` with no other option: an overview of all the data whose
// cell size follows the point density, so that the data covers most of the frame (counted
// from the command's own "(N of M pixels hit)" and checked in the PNG).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "beamtrace/heightfield/las_sources.hpp"
#include "beamtrace/heightfield/view_renderer.hpp"
#include "beamtrace/io/png_reader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// Runs `view` on `input` with defaults only; returns the fraction of pixels hit that it
/// reports, after checking the PNG has the default size.
double default_view_coverage(const fs::path& input, const fs::path& png) {
    const auto r = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " view '" + input.string() +
                                     "' --output '" + png.string() + "' 2>&1");
    EXPECT_EQ(r.exit_code, 0) << r.out;
    // "(N of M pixels hit)" in the summary.
    const std::size_t end = r.out.find(" pixels hit)");
    const std::size_t open = r.out.rfind('(', end);
    unsigned long long hit = 0, all = 0;
    if (end == std::string::npos || open == std::string::npos ||
        std::sscanf(r.out.c_str() + open, "(%llu of %llu", &hit, &all) != 2 || all == 0) {
        ADD_FAILURE() << "no pixel count in: " << r.out;
        return 0.0;
    }
    const double reported = static_cast<double>(hit) / static_cast<double>(all);
    // The same from the image: pixels that differ from the sky colour (ViewRenderSettings).
    const RgbImage image = read_png_rgb8(png);
    EXPECT_EQ(image.width, 1920);
    EXPECT_EQ(image.height, 1080);
    const Rgb8 sky = RenderOptions{}.sky;
    std::size_t data = 0;
    for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
        data += image.rgb[i] != sky[0] || image.rgb[i + 1] != sky[1] || image.rgb[i + 2] != sky[2];
    }
    EXPECT_NEAR(static_cast<double>(data) / (static_cast<double>(image.rgb.size()) / 3.0), reported,
                0.02);
    return reported;
}

TEST(ViewDefaults, CellSizeFollowsThePointDensityOfTheHeaders) {
    const fs::path las = test::shared_data("las/las/autzen_trim.las");
    BEAMTRACE_REQUIRE_FILE(las);
    // 110 000 points on 1177.46 x 562.70 ft: mean spacing 2.453 ft, x 1.5 = 3.68, up to 5.
    const std::vector<fs::path> one = {las};
    EXPECT_EQ(auto_cell_size(LasSourceSet(one)), 5.0);
    // The same file four times: four times the points on four footprints (tiles add up).
    const std::vector<fs::path> four = {las, las, las, las};
    EXPECT_EQ(auto_cell_size(LasSourceSet(four)), 5.0);
}

TEST(ViewDefaults, DefaultOverviewCoversMostOfTheFrameForRealFiles) {
    test::TempDir dir;
    for (const char* name : {"las/las/autzen_trim.las", "las/las/autzen.las"}) {
        const fs::path las = test::shared_data(name);
        BEAMTRACE_REQUIRE_FILE(las);
        EXPECT_GE(default_view_coverage(las, dir / "v.png"), 0.40) << name;
    }
}

TEST(ViewDefaults, DefaultOverviewCoversMostOfTheFrameForAirborneAndCarSurveys) {
    test::TempDir dir;
    for (const char* name : {"airborne_line", "airborne_srtm", "car_hdl64"}) {
        const fs::path out = dir / name;
        const auto r = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " survey " +
                                         BEAMTRACE_EXAMPLES_DIR + "/surveys/" + name +
                                         ".yaml --quiet --output '" + out.string() + "' 2>&1");
        ASSERT_EQ(r.exit_code, 0) << r.out;
        EXPECT_GE(default_view_coverage(out / "points.las", dir / "v.png"), 0.40) << name;
    }
}

TEST(ViewDefaults, PointsLeftOutAreCountedWithTheReason) {
    const fs::path las = test::shared_data("las/las/autzen_trim.las");
    BEAMTRACE_REQUIRE_FILE(las);
    test::TempDir dir;
    // A window of 2x2 sections of 256 ft around the centre: about half the file lies outside.
    auto r = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " view '" + las.string() +
                               "' --cell-size 1 --sections 2x2 --levels 3 --section-cells 64 "
                               "--size 64x36 --output '" +
                               (dir / "v.png").string() + "' 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    unsigned long long hidden = 0, all = 0, shown = 0, read = 0;
    const std::size_t note = r.out.find("beamtrace: note: ");
    ASSERT_NE(note, std::string::npos) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + note, "beamtrace: note: %llu of %llu points not shown",
                          &hidden, &all),
              2)
        << r.out;
    EXPECT_NE(r.out.find("the files reach beyond the window of 2x2 sections of 256 units"),
              std::string::npos)
        << r.out;
    const std::size_t loaded = r.out.find("-unit cells: ");
    ASSERT_NE(loaded, std::string::npos) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + loaded, "-unit cells: %llu of %llu", &shown, &read), 2);
    EXPECT_EQ(all, 110000u);
    EXPECT_EQ(hidden + shown, all);
    EXPECT_GT(hidden, 10000u);
    // The defaults show every point, and say nothing.
    r = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " view '" + las.string() +
                          "' --size 64x36 --output '" + (dir / "w.png").string() + "' 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(r.out.find("not shown"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("110000 of 110000 points"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace beamtrace
