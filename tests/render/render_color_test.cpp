// `render` in colour: a pattern's colours per stripe, a material colour, and a sky.
#include <gtest/gtest.h>

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/png_reader.hpp"
#include "beamtrace/physics/albedo_pattern.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(RenderColor, PatternColoursGoToTheCellsInTurn) {
    AlbedoPattern p;
    p.kind = AlbedoPatternKind::stripes;
    p.size_m = 1.0;
    p.colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const PatternFrame solid;  // stripes along x, 1 m wide
    EXPECT_EQ(pattern_color(p, solid, {0.5, 0, 0}, {1, 1, 1}), (Vec3d{1, 0, 0}));
    EXPECT_EQ(pattern_color(p, solid, {1.5, 0, 0}, {1, 1, 1}), (Vec3d{0, 1, 0}));
    EXPECT_EQ(pattern_color(p, solid, {2.5, 0, 0}, {1, 1, 1}), (Vec3d{0, 0, 1}));
    EXPECT_EQ(pattern_color(p, solid, {3.5, 0, 0}, {1, 1, 1}), (Vec3d{1, 0, 0}));
    EXPECT_EQ(pattern_color(p, solid, {-0.5, 0, 0}, {1, 1, 1}), (Vec3d{0, 0, 1}));  // cell -1
    p.colors.clear();
    EXPECT_EQ(pattern_color(p, solid, {1.5, 0, 0}, {0.2, 0.3, 0.4}), (Vec3d{0.2, 0.3, 0.4}));
}

TEST(RenderColor, TheBeachBallHasColouredStripesUnderASky) {
    test::TempDir dir;
    const auto png = dir / "ball.png";
    const auto r =
        test::run_command(std::string(BEAMTRACE_CLI_PATH) + " render " + BEAMTRACE_EXAMPLES_DIR +
                          "/scenes/beach_ball.yaml --camera -6,-4,3,0,0,40 --look-at "
                          "0,0,0.8 --light dir:-60,45,0.9 --ambient 0.15 --size 160x120 "
                          "--gamma 2.2 --sky --output '" +
                          png.string() + "' 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const RgbImage img = read_png_rgb8(png);
    const auto at = [&](int x, int y) {
        const auto i = 3 * (static_cast<std::size_t>(y) * img.width + x);
        return std::array<int, 3>{img.rgb[i], img.rgb[i + 1], img.rgb[i + 2]};
    };
    const auto sky = at(2, 2);
    EXPECT_GT(sky[2], sky[0]);  // blue above
    EXPECT_GT(sky[2], 150);
    std::size_t red = 0, blue = 0, yellow = 0;
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            const auto c = at(x, y);
            red += c[0] > 2 * c[1] && c[0] > 2 * c[2] && c[0] > 80;
            blue += c[2] > 2 * c[0] && c[2] > 80 && y > img.height / 3;  // the ball, not the sky
            yellow += c[0] > 2 * c[2] && c[1] > 2 * c[2] && c[1] > 80;
        }
    }
    EXPECT_GT(red, 100u);
    EXPECT_GT(blue, 100u);
    EXPECT_GT(yellow, 100u);
}

TEST(RenderColor, BadPatternColoursNameTheKey) {
    const std::string yaml =
        "materials:\n  - name: m\n    pattern: {kind: stripes, colors: [[1, 0, 2]]}\n"
        "parts:\n  - name: p\n    plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 1}\n"
        "    material: m\n";
    try {
        (void)parse_scene_spec(yaml, "s.yaml");
        FAIL() << "accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "materials[0].pattern.colors[0]: every channel must be in [0, 1]"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace beamtrace
