// Several scanners on one platform (`scanners:`): each scanner's pulses from its own mount with
// its own range gate, the LAS scanner channel of each point, output.point_source_id: scanner,
// legs applied to every scanner, the no-echo records' scanner, and the errors of the list.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/sensor/scanner_set.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// In the closed 20 m box room, standing still: scanner 0 a 3-beam rotating head (elevations
/// -10, 0, 10 deg; 1 deg steps, one revolution: 3 x 360 = 1080 pulses) at (-2, 3, 1) on LAS
/// channel 2; scanner 1 a line scanner looking straight down (500 pulses in 0.5 s, +/-20 deg)
/// at (1, -1, 0) on channel 0. Every pulse hits a wall, the floor or the ceiling.
constexpr const char* kTwo = R"(scene: room.yaml
scanners:
  - type: rotating
    beam_elevations_deg: [-10, 0, 10]
    rotation_rate_hz: 10
    azimuth_resolution_deg: 1
    duration_s: 0.1
    range_min_m: 0.5
    range_max_m: 50
    channel: 2
    mount: {lever_arm_m: [-2, 3, 1]}
  - type: line
    pulse_rate_hz: 1000
    scan_rate_hz: 10
    scan_angle_max_deg: 20
    duration_s: 0.5
    range_max_m: 100
    mount: {lever_arm_m: [1, -1, 0], boresight_deg: [0, -90, 0]}
    channel: 0
platform: {type: static, position_m: [0, 0, 0]}
)";

const Vec3d kArm0{-2, 3, 1}, kArm1{1, -1, 0};
const double kElevations[] = {-10.0, 0.0, 10.0};

TEST(SurveyScanners, TwoScannersGiveEachItsPulsesPerChannelFromItsOwnMount) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", test::kBoxRoom);
    const auto points =
        test::run_and_read(std::string(kTwo) + "output: {point_source_id: scanner}\n", dir);
    std::map<int, std::size_t> per_channel;
    double previous_time = -1.0;
    for (const auto& p : points) {
        ++per_channel[p.scanner_channel];
        ASSERT_GE(p.gps_time, previous_time) << "points in GPS time order";
        previous_time = p.gps_time;
        if (p.scanner_channel == 2) {
            ASSERT_EQ(p.point_source_id, 0) << "scanner 0";
            // The beam's elevation seen from scanner 0's mount (1 mm positions at >= 7 m).
            const Vec3d d = Vec3d{p.x, p.y, p.z} - kArm0;
            const double elevation = std::atan2(d.z, std::hypot(d.x, d.y)) / kDeg;
            ASSERT_LT(p.user_data, 3);
            ASSERT_NEAR(elevation, kElevations[p.user_data], 0.02) << p.gps_time;
        } else {
            ASSERT_EQ(p.scanner_channel, 0);
            ASSERT_EQ(p.point_source_id, 1) << "scanner 1";
            // Straight down from (1, -1, 0), swept across y: on the floor under the line x = 1.
            ASSERT_NEAR(p.x, 1.0, 1e-3);
            ASSERT_NEAR(p.z, -5.0, 1e-3);
            ASSERT_NEAR(p.y + 1.0, 5.0 * std::tan(-p.scan_angle_deg * kDeg), 2e-3) << p.gps_time;
        }
    }
    EXPECT_EQ(per_channel, (std::map<int, std::size_t>{{0, 500}, {2, 1080}}));
}

TEST(SurveyScanners, EachPulsesRayLeavesItsScannersMountWithItsRangeGate) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", test::kBoxRoom);
    test::write_file(dir / "survey.yaml", kTwo);
    const SurveySpec spec = load_survey_spec(dir / "survey.yaml");
    ASSERT_EQ(spec.scanners.size(), 2u);
    ThreadPool pool(2);
    const RayBatch rays = survey_rays(spec, 1, 0, pool);
    const auto pattern = spec.make_pattern();
    ASSERT_EQ(rays.size(), 1580u);
    PulseBatch pulses;
    pattern->generate(0, rays.size(), pulses);
    std::size_t of_scanner[2] = {};
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const std::uint8_t s = pulses.scanner[i];
        ASSERT_LT(s, 2);
        ++of_scanner[s];
        const Vec3d arm = s == 0 ? kArm0 : kArm1;
        ASSERT_NEAR(rays.ox[i], arm.x, 1e-12) << i;
        ASSERT_NEAR(rays.oy[i], arm.y, 1e-12) << i;
        ASSERT_NEAR(rays.oz[i], arm.z, 1e-12) << i;
        ASSERT_EQ(rays.tmin[i], s == 0 ? 0.5 : 0.0) << i;
        ASSERT_EQ(rays.tmax[i], s == 0 ? 50.0 : 100.0) << i;
        if (s == 1) {  // boresight pitch -90: the line scanner's +x is straight down
            ASSERT_LT(rays.dz[i], -0.9);
            ASSERT_NEAR(rays.dx[i], 0.0, 1e-12);
        } else {
            ASSERT_NEAR(std::asin(rays.dz[i]) / kDeg, kElevations[pulses.channel[i]], 1e-9);
        }
    }
    EXPECT_EQ(of_scanner[0], 1080u);
    EXPECT_EQ(of_scanner[1], 500u);
}

TEST(SurveyScanners, WithPhysicsEachScannersMountAndTheSameBytesForOneAndTwoThreads) {
    test::TempDir a, b;
    const std::string yaml = std::string(kTwo) +
                             "physics: {beam: {divergence_mrad: 3, rings: 1}, noise: "
                             "{range_sigma_m: 0.01}}\noutput: {csv: true, no_echo: true}\n";
    for (const test::TempDir* d : {&a, &b}) {
        test::write_file(*d / "room.yaml", test::kBoxRoom);
    }
    const auto one = test::run_and_read(yaml, a, 1, 1 << 16);
    (void)test::run_and_read(yaml, b, 2, 1024);
    for (const char* f : {"points.las", "points.csv", "no_echo.csv"}) {
        EXPECT_EQ(test::read_file(a / "out" / f), test::read_file(b / "out" / f)) << f;
    }
    std::map<int, std::size_t> per_channel;
    for (const auto& p : one) {
        ++per_channel[p.scanner_channel];
        if (p.scanner_channel == 0) {  // from scanner 1's mount, straight down: x = 1
            ASSERT_NEAR(p.x, 1.0, 2e-3) << p.gps_time;
            ASSERT_NEAR(p.z, -5.0, 0.1) << p.gps_time;
        }
    }
    EXPECT_EQ(per_channel, (std::map<int, std::size_t>{{0, 500}, {2, 1080}}));
}

/// The single `scanner:` survey and the same scanner as the one entry of `scanners:` on
/// channel 0 give the same points, bit for bit.
TEST(SurveyScanners, OneEntryListGivesTheSingleScannerSurveysPoints) {
    test::TempDir a, b;
    const std::string scanner =
        "{type: line, pulse_rate_hz: 1000, scan_rate_hz: 10, scan_angle_max_deg: 20, "
        "duration_s: 0.5, range_max_m: 100";
    const std::string mount = "{lever_arm_m: [1, -1, 0], boresight_deg: [0, -90, 0]}";
    const std::string rest = "platform: {type: static}\noutput: {csv: true}\n";
    for (const test::TempDir* d : {&a, &b}) {
        test::write_file(*d / "room.yaml", test::kBoxRoom);
    }
    const auto single = test::run_and_read(
        "scene: room.yaml\nscanner: " + scanner + "}\nmount: " + mount + "\n" + rest, a);
    const auto listed = test::run_and_read(
        "scene: room.yaml\nscanners:\n  - " + scanner + ", mount: " + mount + "}\n" + rest, b);
    ASSERT_EQ(single.size(), 500u);
    EXPECT_EQ(single, listed);
    // points.csv: the same rows, plus the scanner_channel column (0) with `scanners:`.
    std::istringstream in(test::read_file(a / "out" / "points.csv"));
    std::string want;
    for (std::string line; std::getline(in, line);) {
        want += line + (want.empty() ? ",scanner_channel\n" : ",0\n");
    }
    EXPECT_EQ(test::read_file(b / "out" / "points.csv"), want);
}

TEST(SurveyScanners, LegOverridesApplyToEveryScannerAndInactiveTurnsThemAllOff) {
    test::TempDir dir;
    test::write_file(dir / "plane.yaml",
                     "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 2000}\n");
    // Leg 0: [0, 2) s, scanner 0 at 1 kHz, scanner 1 at 500 Hz; leg 1: [2, 3) s, off; leg 2:
    // [3, 5) s, both at 2 kHz (the leg's pulse_rate_hz for every scanner).
    const auto points = test::run_and_read(R"(scene: plane.yaml
scanners:
  - {type: line, pulse_rate_hz: 1000, scan_rate_hz: 10, scan_angle_max_deg: 20, waveform: triangle,
     mount: {lever_arm_m: [0, 2, 0], boresight_deg: [0, -90, 0]}}
  - {type: line, pulse_rate_hz: 500, scan_rate_hz: 10, scan_angle_max_deg: 10, waveform: triangle,
     mount: {lever_arm_m: [0, -2, 0], boresight_deg: [0, -90, 0]}, channel: 3}
platform:
  type: legs
  speed_mps: 50
  waypoints_m: [[0, 0, 100], [100, 0, 100], [100, 50, 100], [0, 50, 100]]
  legs:
    - {}
    - scanner: {active: false}
    - scanner: {pulse_rate_hz: 2000}
output: {point_source_id: leg}
)",
                                           dir);
    std::map<std::pair<int, int>, std::size_t> count;  // (leg, channel)
    for (const auto& p : points) {
        ++count[{p.point_source_id, p.scanner_channel}];
        ASSERT_FALSE(p.gps_time >= 2.0 && p.gps_time < 3.0) << "a point on the turn";
        ASSERT_EQ(p.point_source_id, p.gps_time < 2.0 ? 0 : 2) << p.gps_time;
        // Each scanner's nadir line is offset by its lever arm: +/-2 m to the left of travel.
        const double left = p.point_source_id == 0 ? p.y : 50.0 - p.y;
        const double arm = p.scanner_channel == 0 ? 2.0 : -2.0;
        ASSERT_NEAR(std::abs(left - arm), 100.0 * std::tan(std::abs(p.scan_angle_deg) * kDeg), 0.02)
            << p.gps_time;
    }
    EXPECT_EQ(count, (std::map<std::pair<int, int>, std::size_t>{
                         {{0, 0}, 2000}, {{0, 3}, 1000}, {{2, 0}, 4000}, {{2, 3}, 4000}}));
}

TEST(SurveyScanners, NoEchoRecordsCarryTheScannerIndex) {
    test::TempDir dir;
    test::write_file(dir / "plane.yaml",
                     "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 200}\n");
    // Scanner 0 looks down at the plane (every pulse hits), scanner 1 looks up (none does).
    const auto points = test::run_and_read(R"(scene: plane.yaml
scanners:
  - {type: line, pulse_rate_hz: 1000, duration_s: 0.2, mount: {boresight_deg: [0, -90, 0]}}
  - {type: line, pulse_rate_hz: 300, duration_s: 0.2, mount: {boresight_deg: [0, 90, 0]}}
platform: {type: static, position_m: [0, 0, 10]}
output: {no_echo: true}
)",
                                           dir);
    EXPECT_EQ(points.size(), 200u);
    std::istringstream in(test::read_file(dir / "out" / "no_echo.csv"));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "pulse,gps_time,ox,oy,oz,dx,dy,dz,scanner");
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        ++rows;
        ASSERT_EQ(line.substr(line.rfind(',') + 1), "1") << line;
    }
    EXPECT_EQ(rows, 60u);
}

/// The message of the ConfigError that parsing `yaml` throws ("" if none).
std::string error_of(const std::string& yaml) {
    try {
        (void)parse_survey_spec(yaml, "survey.yaml");
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

TEST(SurveyScanners, BadListsAreErrorsWithFileLineAndKey) {
    const std::string platform = "platform: {type: static}\n";
    const std::string line = "{type: line, duration_s: 0.01";
    EXPECT_NE(error_of("scene: demo\nscanners:\n  - " + line + ", channel: 1}\n  - " + line +
                       ", channel: 1}\n" + platform)
                  .find("survey.yaml:4: scanners[1].channel: channel 1 is already another "
                        "scanner's"),
              std::string::npos);
    EXPECT_NE(error_of("scene: demo\nscanners:\n  - " + line + ", channel: 4}\n" + platform)
                  .find("survey.yaml:3: scanners[0].channel: expected an integer in [0, 3]"),
              std::string::npos);
    EXPECT_NE(
        error_of("scene: demo\nscanner: " + line + "}\nscanners:\n  - " + line + "}\n" + platform)
            .find("survey.yaml:4: scanners: not with scanner:"),
        std::string::npos);
    EXPECT_NE(error_of("scene: demo\nmount: {}\nscanners:\n  - " + line + "}\n" + platform)
                  .find("survey.yaml:2: mount: not with scanners:"),
              std::string::npos);
    std::string five = "scene: demo\nscanners:\n";
    for (int i = 0; i < 5; ++i) {
        five += "  - " + line + "}\n";
    }
    EXPECT_NE(error_of(five + platform).find("survey.yaml:3: scanners: expected a list of 1 to 4"),
              std::string::npos);
    EXPECT_NE(
        error_of("scene: demo\nscanners:\n  - " + line + ", spin_clockwise: true}\n" + platform)
            .find("survey.yaml:3: scanners[0].spin_clockwise: unknown key for a line "
                  "scanner"),
        std::string::npos);
    EXPECT_NE(error_of("scene: demo\nscanners:\n  - " + line + ", mount: {lever_arm_m: [1, 2]}}\n" +
                       platform)
                  .find("survey.yaml:3: scanners[0].mount.lever_arm_m:"),
              std::string::npos);
    // Without channels: the index in the list.
    const SurveySpec spec = parse_survey_spec(
        "scene: demo\nscanners:\n  - " + line + "}\n  - " + line + "}\n" + platform, "s.yaml");
    ASSERT_EQ(spec.scanners.size(), 2u);
    EXPECT_EQ(spec.scanners[0].channel, 0);
    EXPECT_EQ(spec.scanners[1].channel, 1);
}

}  // namespace
}  // namespace beamtrace
