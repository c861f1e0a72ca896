// Angles on command lines: `scan` keeps radians but takes an explicit unit and warns about a
// radians option beyond a full turn; camera yaw and pitch take units too.
#include <gtest/gtest.h>

#include <string>

#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

std::string cli(const std::string& args) {
    return std::string(BEAMTRACE_CLI_PATH) + " " + args;
}

TEST(UnitsCli, ScanTakesDegreesWhenSaidAndWarnsAboutDegreesInRadians) {
    test::TempDir dir;
    const std::string common = "scan --demo --width 40 --height 20 --quiet --output ";
    const auto deg = test::run_command(
        cli(common + "'" + (dir / "d").string() + "' --orientation 0,-30deg,0 --hfov 60deg 2>&1"));
    ASSERT_EQ(deg.exit_code, 0) << deg.out;
    EXPECT_FALSE(has(deg.out, "warning")) << deg.out;
    const auto rad = test::run_command(
        cli(common + "'" + (dir / "r").string() +
            "' --orientation 0,-0.5235987755982988,0 --hfov 1.0471975511965976 2>&1"));
    ASSERT_EQ(rad.exit_code, 0) << rad.out;
    EXPECT_EQ(test::read_file(dir / "d" / "points.ply"), test::read_file(dir / "r" / "points.ply"));

    const auto big = test::run_command(
        cli(common + "'" + (dir / "b").string() + "' --orientation 0,-90,0 2>&1"));
    EXPECT_TRUE(has(big.out, "warning: --orientation: -90 rad is more than a full turn"))
        << big.out;
    EXPECT_TRUE(has(big.out, "write -90deg")) << big.out;

    const auto bad =
        test::run_command(cli(common + "'" + (dir / "x").string() + "' --hfov 60x 2>&1"));
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_TRUE(has(bad.out, "--hfov expects an angle in radians")) << bad.out;
}

TEST(UnitsCli, CameraYawAndPitchTakeUnits) {
    test::TempDir dir;
    const fs::path las = test::shared_data("las/las/autzen_trim.las");
    BEAMTRACE_REQUIRE_FILE(las);
    std::string images[2];
    const char* cameras[2] = {"636237,849047,670,-25,-30", "636237,849047,670,-25deg,-30\xC2\xB0"};
    for (int k = 0; k < 2; ++k) {
        const fs::path png = dir / ("v" + std::to_string(k) + ".png");
        const auto r =
            test::run_command(cli("view '" + las.string() + "' --camera " + cameras[k] +
                                  " --size 80x45 --quiet --output '" + png.string() + "' 2>&1"));
        ASSERT_EQ(r.exit_code, 0) << r.out;
        images[k] = test::read_file(png);
    }
    EXPECT_EQ(images[0], images[1]);
}

}  // namespace
}  // namespace beamtrace
