// Surveys that give no or very few points say why, and an empty result exits 3 unless
// --allow-empty: the scanner looking away (a line scanner without a boresight), a range gate
// that excludes every hit, a detection threshold above every echo.
#include <gtest/gtest.h>

#include <string>

#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

test::RunResult survey(const test::TempDir& dir, const std::string& yaml,
                       const std::string& flags = "") {
    const fs::path file = dir / "s.yaml";
    test::write_file(file, yaml);
    return test::run_command(std::string(BEAMTRACE_CLI_PATH) + " survey '" + file.string() +
                             "' --quiet --output '" + (dir / "out").string() + "' " + flags +
                             " 2>&1");
}

const std::string kLine =
    "scene: demo\n"
    "scanner: {type: line, pulse_rate_hz: 10000, scan_rate_hz: 20, scan_angle_max_deg: 20, "
    "duration_s: 0.2}\n"
    "platform: {type: static, position_m: [0, 0, 150]}\n";

TEST(Plausibility, ALineScannerLookingAtTheHorizonSaysSoAndExits3) {
    test::TempDir dir;
    const auto r = survey(dir, kLine);
    EXPECT_EQ(r.exit_code, 3) << r.out;
    EXPECT_TRUE(has(r.out, "warning: 0 of 2000 pulses gave points")) << r.out;
    EXPECT_TRUE(has(r.out, "none hits the scene (1024 do not even point at its bounding box)"))
        << r.out;
    EXPECT_TRUE(has(r.out, "boresight_deg: [0, -90, 0] turns it down")) << r.out;
    EXPECT_TRUE(has(r.out, "--allow-empty")) << r.out;
    EXPECT_TRUE(fs::exists(dir / "out" / "points.las"));

    const auto allowed = survey(dir, kLine, "--allow-empty");
    EXPECT_EQ(allowed.exit_code, 0) << allowed.out;
    EXPECT_TRUE(has(allowed.out, "none hits the scene")) << allowed.out;

    const auto down = survey(dir, kLine + "mount: {boresight_deg: [0, -90, 0]}\n");
    EXPECT_EQ(down.exit_code, 0) << down.out;
    EXPECT_FALSE(has(down.out, "warning")) << down.out;
}

TEST(Plausibility, ARangeGateBeyondEveryHitAndAThresholdAboveEveryEchoAreNamed) {
    test::TempDir dir;
    const std::string down = kLine + "mount: {boresight_deg: [0, -90, 0]}\n";
    const auto gate =
        survey(dir,
               "scene: demo\nscanner: {type: line, pulse_rate_hz: 10000, scan_rate_hz: 20, "
               "scan_angle_max_deg: 20, duration_s: 0.2, range_min_m: 500, range_max_m: 900}\n"
               "platform: {type: static, position_m: [0, 0, 150]}\nmount: {boresight_deg: [0, "
               "-90, 0]}\n");
    EXPECT_EQ(gate.exit_code, 3) << gate.out;
    EXPECT_TRUE(has(gate.out,
                    "none of them inside the range gate "
                    "scanner.range_min_m..range_max_m = 500.0..900.0 m"))
        << gate.out;

    const auto threshold = survey(dir, down + "physics: {detection_threshold_w: 10}\n");
    EXPECT_EQ(threshold.exit_code, 3) << threshold.out;
    EXPECT_TRUE(has(threshold.out, "physics.detection_threshold_w (10 W) may be above every echo"))
        << threshold.out;
}

TEST(Plausibility, AScanThatHitsNothingSaysWhereItLooks) {
    test::TempDir dir;
    const std::string scan = std::string(BEAMTRACE_CLI_PATH) +
                             " scan --demo --width 40 --height 20 --quiet --orientation 0,90deg,0 "
                             "--output '" +
                             (dir / "s").string() + "'";
    const auto r = test::run_command(scan + " 2>&1");
    EXPECT_EQ(r.exit_code, 3) << r.out;
    EXPECT_TRUE(has(r.out,
                    "warning: 0 of 800 rays hit the scene; 800 do not even point at its "
                    "bounding box"))
        << r.out;
    EXPECT_TRUE(has(r.out, "check --position and --orientation")) << r.out;
    EXPECT_EQ(test::run_command(scan + " --allow-empty 2>&1").exit_code, 0);
}

}  // namespace
}  // namespace beamtrace
