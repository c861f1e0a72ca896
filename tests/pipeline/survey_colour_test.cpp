// Point formats 7 and 8: each point's RGB is its material's colour (sRGB, 16 bits) and its NIR
// the material's reflectance.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "beamtrace/io/las_reader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(SurveyColour, Formats7And8CarryTheMaterialColourAndReflectance) {
    test::TempDir dir;
    test::write_file(dir / "scene.yaml",
                     "materials:\n  - {name: orange, reflectance: 0.25, color: [1, 0.5, 0]}\n"
                     "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 100}\n"
                     "    material: orange\n");
    const double s = 1.055 * std::pow(0.5, 1.0 / 2.4) - 0.055;  // sRGB of linear 0.5
    for (const int format : {6, 7, 8}) {
        SCOPED_TRACE(format);
        test::write_file(dir / "s.yaml",
                         "scene: scene.yaml\nscanner: {type: line, pulse_rate_hz: 1000, "
                         "scan_rate_hz: 10, scan_angle_max_deg: 10, duration_s: 0.1}\n"
                         "platform: {type: static, position_m: [0, 0, 20]}\n"
                         "mount: {boresight_deg: [0, -90, 0]}\noutput: {point_format: " +
                             std::to_string(format) + ", preview: false}\n");
        const auto out = dir / ("out" + std::to_string(format));
        const auto r = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " survey '" +
                                         (dir / "s.yaml").string() + "' --quiet --output '" +
                                         out.string() + "' 2>&1");
        ASSERT_EQ(r.exit_code, 0) << r.out;
        LasReader las(out / "points.las");
        std::vector<LasPoint> points(static_cast<std::size_t>(las.header().point_count));
        ASSERT_EQ(las.read(points), points.size());
        ASSERT_GT(points.size(), 50u);
        for (const LasPoint& p : points) {
            EXPECT_EQ(p.red, format >= 7 ? 65535 : 0);
            EXPECT_EQ(p.green, format >= 7 ? std::lround(s * 65535.0) : 0);
            EXPECT_EQ(p.blue, 0);
            EXPECT_EQ(p.nir, format == 8 ? std::lround(0.25 * 65535.0) : 0);
        }
    }
}

}  // namespace
}  // namespace beamtrace
