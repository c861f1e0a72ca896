// The interactive window of `beamtrace view`, run headless under Xvfb: a few frames, then a
// screenshot read back with glReadPixels that must match the offline render of the same camera.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "beamtrace/io/png_reader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

class ViewWindow : public test::TempDirTest {
  protected:
    void SetUp() override {
        las_ = test::shared_data("las/las/autzen_trim.las");
        BEAMTRACE_REQUIRE_FILE(las_);
    }
    [[nodiscard]] std::string view(const std::string& args) const {
        return std::string(BEAMTRACE_CLI_PATH) + " view '" + las_.string() +
               "' --cell-size 2 --levels 5 --section-cells 8 --size 240x135 --threads 2 "
               "--color rgb --fog 3000 --camera 636237,849047,670,-25,-30 " +
               args;
    }
    std::filesystem::path las_;
};

TEST_F(ViewWindow, HeadlessScreenshotMatchesTheOfflineRender) {
#ifndef BEAMTRACE_HAVE_GLFW
    const auto r = test::run_command(view("--interactive"));
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find("built without GLFW"), std::string::npos) << r.out;
    BEAMTRACE_SKIP_OR_FAIL("beamtrace was built without GLFW/OpenGL (libglfw3-dev)");
#else
    if (test::run_command("command -v xvfb-run").exit_code != 0) {
        BEAMTRACE_SKIP_OR_FAIL("xvfb-run not found (apt install xvfb xauth)");
    }
    const auto shot = dir_ / "shot.png";
    const auto offline = dir_ / "offline.png";
    // A 24-bit screen: Xvfb's default depth has no GLX visual for the window.
#ifdef BEAMTRACE_SANITIZED
    // Mesa's GL driver keeps allocations until exit: not ours to report.
    const std::string env = "ASAN_OPTIONS=detect_leaks=0 ";
#else
    const std::string env;
#endif
    auto r =
        test::run_command(env + "xvfb-run -a -s '-screen 0 640x480x24' " +
                          view("--interactive --frames 4 --screenshot '" + shot.string() + "'"));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("4 frames"), std::string::npos) << r.out;
    r = test::run_command(view("--quiet --output '" + offline.string() + "'"));
    ASSERT_EQ(r.exit_code, 0) << r.out;

    const RgbImage a = read_png_rgb8(shot);
    const RgbImage b = read_png_rgb8(offline);
    ASSERT_EQ(a.width, 240);
    ASSERT_EQ(a.height, 135);
    ASSERT_EQ(b.width, a.width);
    ASSERT_EQ(b.height, a.height);
    // Non-trivial: most pixels are neither black (nothing drawn) nor the sky.
    std::size_t ground = 0, close = 0;
    const std::size_t pixels = a.rgb.size() / 3;
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::uint8_t* p = &a.rgb[3 * i];
        const std::uint8_t* q = &b.rgb[3 * i];
        const bool sky = p[0] == 150 && p[1] == 180 && p[2] == 220;
        const bool black = p[0] == 0 && p[1] == 0 && p[2] == 0;
        ground += !sky && !black ? 1 : 0;
        close +=
            std::abs(p[0] - q[0]) <= 2 && std::abs(p[1] - q[1]) <= 2 && std::abs(p[2] - q[2]) <= 2
                ? 1
                : 0;
    }
    EXPECT_GT(ground, pixels / 3);
    EXPECT_GE(close, pixels * 99 / 100);
#endif
}

TEST_F(ViewWindow, ScreenshotOptionsNeedTheWindow) {
    const auto r =
        test::run_command(view("--frames 3 --output '" + (dir_ / "x.png").string() + "'"));
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find("--interactive"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace beamtrace
