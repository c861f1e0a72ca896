// Surveys of legs, each with its own scanner settings or the scanner off (platform.legs), the
// LAS point source ID per leg (output.point_source_id: leg), and the records of pulses with no
// echo (output.no_echo: no_echo.csv).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr const char* kPlane =
    "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 2000}\n";

/// Leg 0: 100 m east in [0, 2) s at 1 kHz, +/-20 deg; leg 1: the 50 m turn in [2, 3) s,
/// scanner off; leg 2: 100 m west in [3, 5) s at 2 kHz, +/-10 deg; 100 m over a plane.
constexpr const char* kLegs = R"(scene: plane.yaml
scanner: {type: line, pulse_rate_hz: 1000, scan_rate_hz: 10, scan_angle_max_deg: 20, waveform: triangle}
platform:
  type: legs
  speed_mps: 50
  waypoints_m: [[0, 0, 100], [100, 0, 100], [100, 50, 100], [0, 50, 100]]
  legs:
    - {}
    - scanner: {active: false}
    - scanner: {pulse_rate_hz: 2000, scan_angle_max_deg: 10}
mount: {boresight_deg: [0, -90, 0]}
)";

TEST(SurveyLegs, ScannerOffOnTheTurnAndPerLegRatesGiveTheCountsPerLeg) {
    test::TempDir dir;
    test::write_file(dir / "plane.yaml", kPlane);
    const auto points =
        test::run_and_read(std::string(kLegs) + "output: {point_source_id: leg}\n", dir);
    std::map<int, std::size_t> per_leg;
    std::map<int, float> widest;
    for (const auto& p : points) {
        ++per_leg[p.point_source_id];
        widest[p.point_source_id] = std::max(widest[p.point_source_id], std::abs(p.scan_angle_deg));
        ASSERT_NEAR(p.z, 0.0, 1e-3);
        ASSERT_FALSE(p.gps_time >= 2.0 && p.gps_time < 3.0) << "a point on the turn";
        if (p.point_source_id == 0) {
            ASSERT_LT(p.gps_time, 2.0);
            // Nadir lines across track: the point is under the platform at its pulse's time.
            ASSERT_NEAR(p.x, 50.0 * p.gps_time, 2e-3) << p.gps_time;
            ASSERT_NEAR(std::abs(p.y),
                        100.0 * std::tan(std::abs(p.scan_angle_deg) * std::numbers::pi / 180.0),
                        0.02);
        } else {
            ASSERT_EQ(p.point_source_id, 2);
            ASSERT_GE(p.gps_time, 3.0);
            ASSERT_LT(p.gps_time, 5.0);
            ASSERT_NEAR(p.x, 100.0 - 50.0 * (p.gps_time - 3.0), 2e-3) << p.gps_time;
            ASSERT_NEAR(std::abs(p.y - 50.0),
                        100.0 * std::tan(std::abs(p.scan_angle_deg) * std::numbers::pi / 180.0),
                        0.02);
        }
    }
    // 2 s at 1 kHz, none on the turn, 2 s at 2 kHz: every pulse hits the plane.
    EXPECT_EQ(per_leg, (std::map<int, std::size_t>{{0, 2000}, {2, 4000}}));
    EXPECT_NEAR(widest[0], 20.0f, 0.1f);
    EXPECT_NEAR(widest[2], 10.0f, 0.1f);
}

TEST(SurveyLegs, SameBytesForOneAndTwoThreads) {
    test::TempDir a, b;
    test::write_file(a / "plane.yaml", kPlane);
    test::write_file(b / "plane.yaml", kPlane);
    const std::string yaml =
        std::string(kLegs) + "output: {point_source_id: leg, csv: true, no_echo: true}\n";
    (void)test::run_and_read(yaml, a, 1, 1 << 16);
    (void)test::run_and_read(yaml, b, 2, 3000);
    for (const char* f : {"points.las", "points.csv", "no_echo.csv", "trajectory.csv"}) {
        EXPECT_EQ(test::read_file(a / "out" / f), test::read_file(b / "out" / f)) << f;
    }
    EXPECT_EQ(test::read_file(a / "out" / "no_echo.csv"), "pulse,gps_time,ox,oy,oz,dx,dy,dz\n");
}

/// One row of no_echo.csv.
struct NoEchoRow {
    std::uint64_t pulse = 0;
    double t = 0, o[3] = {}, d[3] = {};
};

std::vector<NoEchoRow> read_no_echo(const std::filesystem::path& path) {
    std::istringstream in(test::read_file(path));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "pulse,gps_time,ox,oy,oz,dx,dy,dz");
    std::vector<NoEchoRow> rows;
    while (std::getline(in, line)) {
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream f(line);
        NoEchoRow r;
        f >> r.pulse >> r.t >> r.o[0] >> r.o[1] >> r.o[2] >> r.d[0] >> r.d[1] >> r.d[2];
        EXPECT_TRUE(f && f.eof()) << line;
        rows.push_back(r);
    }
    return rows;
}

TEST(SurveyLegs, NoEchoRecordsEveryPulseThatMissedWithItsTimeOriginAndDirection) {
    // A 100 m plate under a 200 m flight: the pulses fired before x = -50 and after x = 50 miss.
    test::TempDir dir;
    test::write_file(dir / "plate.yaml",
                     "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 100}\n");
    const auto points = test::run_and_read(R"(scene: plate.yaml
scanner: {type: line, pulse_rate_hz: 500, scan_rate_hz: 10, scan_angle_max_deg: 20, waveform: triangle, duration_s: 4}
platform: {type: legs, speed_mps: 50, waypoints_m: [[-100, 0, 100], [100, 0, 100]]}
mount: {boresight_deg: [0, -90, 0]}
output: {no_echo: true}
)",
                                           dir);
    const std::vector<NoEchoRow> rows = read_no_echo(dir / "out" / "no_echo.csv");
    ASSERT_EQ(rows.size() + points.size(), 2000u);
    std::set<double> times;
    for (const auto& p : points) {
        times.insert(p.gps_time);
    }
    std::uint64_t previous = 0;
    for (const NoEchoRow& r : rows) {
        ASSERT_TRUE(rows.front().pulse == r.pulse || r.pulse > previous) << "pulse order";
        previous = r.pulse;
        EXPECT_EQ(r.t, static_cast<double>(r.pulse) / 500.0) << r.pulse;
        EXPECT_EQ(times.count(r.t), 0u) << "a pulse with a point is listed: " << r.pulse;
        EXPECT_NEAR(r.o[0], -100.0 + 50.0 * r.t, 1e-9);
        EXPECT_NEAR(r.o[1], 0.0, 1e-9);
        EXPECT_NEAR(r.o[2], 100.0, 1e-9);
        EXPECT_NEAR(std::hypot(r.d[0], r.d[1], r.d[2]), 1.0, 1e-12);
        // Brute force: where the beam meets z = 0, it is off the plate.
        ASSERT_LT(r.d[2], 0.0);
        const double s = -r.o[2] / r.d[2];
        const double x = r.o[0] + s * r.d[0], y = r.o[1] + s * r.d[1];
        EXPECT_TRUE(std::abs(x) > 50.0 || std::abs(y) > 50.0) << r.pulse << ": " << x << " " << y;
    }
    // The plate spans x in [-50, 50]: t in [1, 3], 1000 pulses of the 2000 (within a pulse).
    EXPECT_NEAR(static_cast<double>(points.size()), 1000.0, 2.0);
}

/// The ALS50-II mirror's angle (degrees, positive to the left) u seconds into a line of period
/// T, turning in D seconds at each end (line_scanner.hpp): -max at the start of even lines,
/// constant speed w between the turns, odd lines the mirror image.
double als50ii_mirror_deg(double u, long line) {
    const double max = 60.0, T = 0.01, h = (1.0 / 700.0) / 2.0, w = 2.0 * max / (T - h);
    double s = 0.0;
    if (u < h) {
        s = -max + w * u * u / (2.0 * h);
    } else if (u > T - h) {
        s = max - w * (T - u) * (T - u) / (2.0 * h);
    } else {
        s = -max + w * h / 2.0 + w * (u - h);
    }
    return line % 2 == 0 ? s : -s;
}

/// examples/surveys/als50ii.yaml (HELIOS++'s als_hd_demo): two 2 s legs flown in opposite
/// directions, the scanner off on the 2 s turn between them. The data sheet's figures: 100
/// lines/s of 700 pulses (70 kHz, 50 Hz mirror); the mirror model: every point's scan angle
/// that of the triangle with 100-pulse turns at its time into the leg, and every point at the
/// ground offset its scan angle gives from 1500 m: |y - y_leg| = (1500 - z) tan |s|.
TEST(SurveyLegs, Als50IIExampleHasTheLineRatePointsPerLineAndSwathAndNothingOnTheTurn) {
    test::TempDir dir;
    SurveyRunConfig run;
    run.output_dir = dir / "out";
    (void)run_survey(load_survey_spec(std::filesystem::path(BEAMTRACE_EXAMPLES_DIR) / "surveys" /
                                      "als50ii.yaml"),
                     run);
    const auto points = read_las_points(dir / "out" / "points.las");
    ASSERT_EQ(points.size(), 280'000u) << "2 x 2 s at 70 kHz, every pulse on the DEM";
    std::map<long, std::size_t> per_line;
    float lo = 0, hi = 0;
    for (const auto& p : points) {
        ASSERT_FALSE(p.gps_time >= 2.0 && p.gps_time < 4.0) << "a point on the turn";
        const bool back = p.gps_time >= 4.0;  // the second leg, flown westwards at y = 300
        const double u_leg = p.gps_time - (back ? 4.0 : 0.0);
        const long line = static_cast<long>(std::floor(u_leg * 100.0 + 1e-9));
        ++per_line[line + (back ? 1000 : 0)];
        lo = std::min(lo, p.scan_angle_deg);
        hi = std::max(hi, p.scan_angle_deg);
        // LAS: positive to the right of travel, the mirror's angle positive to the left.
        const double mirror = als50ii_mirror_deg(u_leg - static_cast<double>(line) * 0.01, line);
        ASSERT_NEAR(p.scan_angle_deg, -mirror, 0.004) << p.gps_time;
        const double y = p.y - 5473888.0 - (back ? 300.0 : 0.0);  // the scene's origin_m
        const double s = std::abs(p.scan_angle_deg) * std::numbers::pi / 180.0;
        // LAS keeps the angle in 0.006 deg steps: up to 0.003 deg, x4 at 60 deg, ~0.3 m at 1.4 km.
        ASSERT_NEAR(std::abs(y), (1500.0 - p.z) * std::tan(s), 0.5) << p.gps_time;
        ASSERT_NEAR(p.x - 478335.0, back ? 150.0 - 150.0 * u_leg : -150.0 + 150.0 * u_leg,
                    std::abs(y) * 1e-3 + 0.01)
            << "under the platform, lines across track";
    }
    ASSERT_EQ(per_line.size(), 400u);  // 100 lines/s for 2 s, twice
    for (const auto& [line, n] : per_line) {
        ASSERT_EQ(n, 700u) << "line " << line;
    }
    EXPECT_NEAR(hi, 60.0, 0.006);
    EXPECT_NEAR(lo, -60.0, 0.006);
}

/// The ConfigError of a survey file, or "" when it loads.
std::string load_error(const test::TempDir& dir, const std::string& yaml) {
    test::write_file(dir / "bad.yaml", yaml);
    try {
        (void)load_survey_spec(dir / "bad.yaml");
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

TEST(SurveyLegs, LegErrorsNameTheFileLineAndKey) {
    test::TempDir dir;
    test::write_file(dir / "plane.yaml", kPlane);
    const std::string head =
        "scene: plane.yaml\nscanner: {type: line, pulse_rate_hz: 1000}\nplatform:\n  type: legs\n"
        "  waypoints_m: [[0, 0, 100], [100, 0, 100], [100, 50, 100]]\n";
    const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
        {head + "  legs: [{}]\n", {"bad.yaml:6: platform.legs: expected a list of 2 legs"}},
        {head + "  legs:\n    - scanner: {pulse_rate_hz: -5, colour: red}\n"
                "    - scanner: {active: maybe}\n",
         {"bad.yaml:7: platform.legs[0].scanner.colour: unknown key",
          "bad.yaml:7: scanner.pulse_rate_hz: must be positive",
          "bad.yaml:8: platform.legs[1].scanner.active: expected true or false"}},
        {head + "  legs: [{}, {scanner: {duration_s: 3}}, {}]\n",
         {"bad.yaml:6: platform.legs: expected a list of 2 legs"}},
        {head + "  legs: [{}, {scanner: {duration_s: 3}}]\n",
         {"bad.yaml:6: platform.legs[1].scanner.duration_s: unknown key"}},
        {"scene: plane.yaml\nscanner: {type: line, pulse_rate_hz: 1000, duration_s: 1}\n"
         "platform: {type: legs, waypoints_m: [[0, 0, 100], [100, 0, 100]], legs: [{}]}\n",
         {"bad.yaml:2: scanner.duration_s: not with platform.legs"}},
        // 1 mm at 50 m/s is 20 us: not one pulse at 1 kHz.
        {"scene: plane.yaml\nscanner: {type: line, pulse_rate_hz: 1000}\n"
         "platform: {type: legs, waypoints_m: [[0, 0, 100], [0.001, 0, 100]], legs: [{}]}\n",
         {"bad.yaml:3: platform.legs[0]: duration_s"}},
        {"scene: plane.yaml\nscanner: {type: line, pulse_rate_hz: 1000}\n"
         "platform: {type: legs, waypoints_m: [[0, 0, 100], [100, 0, 100]]}\n"
         "output: {point_source_id: leg}\n",
         {"bad.yaml:4: output.point_source_id: leg needs platform.legs"}},
        {head + "output: {point_source_id: flight}\n",
         {"bad.yaml:6: output.point_source_id: expected part, leg or scanner"}},
        {"scene: plane.yaml\nscanner: {type: pinhole}\n"
         "platform: {type: legs, waypoints_m: [[0, 0, 100], [100, 0, 100]], legs: [{}]}\n",
         {"bad.yaml:3: platform.legs[0]: a pinhole scanner cannot fire for a leg"}},
    };
    for (const auto& [yaml, needles] : cases) {
        const std::string msg = load_error(dir, yaml);
        for (const std::string& needle : needles) {
            EXPECT_NE(msg.find(needle), std::string::npos) << needle << "\n" << msg << "\n" << yaml;
        }
    }
    // A well-formed file with legs loads, each leg with its settings.
    const std::string ok = load_error(
        dir, head + "  legs: [{scanner: {pulse_rate_hz: 3000}}, {scanner: {active: false}}]\n");
    EXPECT_EQ(ok, "");
    const SurveySpec spec = load_survey_spec(dir / "bad.yaml");
    ASSERT_EQ(spec.leg_scanners.size(), 2u);
    EXPECT_FALSE(spec.leg_scanners[1].active);
    const auto pattern = spec.make_pattern();
    EXPECT_EQ(pattern->pulse_count(), 2u * 3000u) << "100 m at 50 m/s, 3 kHz";
    EXPECT_DOUBLE_EQ(pattern->end_time_s(), 2.0);
    // A leg shared through a YAML alias is read the same each time.
    EXPECT_EQ(load_error(dir, head.substr(0, head.find("  waypoints_m")) +
                                  "  waypoints_m: [[0, 0, 100], [100, 0, 100], [100, 50, 100], "
                                  "[0, 50, 100]]\n  legs: [&off {scanner: {active: false, "
                                  "pulse_rate_hz: 5}}, {}, *off]\n"),
              "");
    const SurveySpec aliased = load_survey_spec(dir / "bad.yaml");
    ASSERT_EQ(aliased.leg_scanners.size(), 3u);
    EXPECT_FALSE(aliased.leg_scanners[0].active);
    EXPECT_TRUE(aliased.leg_scanners[1].active);
    EXPECT_FALSE(aliased.leg_scanners[2].active);
}

}  // namespace
}  // namespace beamtrace
