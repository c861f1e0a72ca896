// The data-sheet presets of the rotating scanner in surveys: a VLP-16 in a closed box room
// returns every pulse, each laser at its documented elevation, with the revolutions cut where
// the firing timing puts them; a beam table from a CSV file next to the survey.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/beam_table.hpp"
#include "beamtrace/sensor/rotating_presets.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

using test::kBoxRoom;

TEST(SurveySensorPresets, Vlp16InABoxRoomGivesThePointsPerRevolutionPerLaser) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", kBoxRoom);
    const auto points = test::run_and_read(R"(scene: room.yaml
scanner: {type: rotating, preset: velodyne_vlp16, duration_s: 0.2}
platform: {type: static, position_m: [1, 2, 0]}
output: {trajectory_rate_hz: 0}
)",
                                           dir);
    // 0.2 s / 55.296 us = 3616.9: 3616 whole firing cycles of 16 lasers, every one returned.
    ASSERT_EQ(points.size(), 16u * 3616u) << "a closed room returns every pulse";
    constexpr double kElevationDeg[16] = {-15, 1, -13, 3,  -11, 5,  -9, 7,
                                          -7,  9, -5,  11, -3,  13, -1, 15};
    std::map<int, std::map<int, std::size_t>> per_revolution_laser;
    for (const auto& p : points) {
        ASSERT_LT(p.user_data, 16);
        const double elevation_deg =
            std::atan2(p.z, std::hypot(p.x - 1.0, p.y - 2.0)) * 180.0 / std::numbers::pi;
        ASSERT_NEAR(elevation_deg, kElevationDeg[p.user_data], 0.01);
        ++per_revolution_laser[static_cast<int>(std::floor(p.gps_time * 10.0))][p.user_data];
    }
    // Revolution 0 is [0, 0.1 s): laser b of cycle k fires at k x 55.296 + b x 2.304 us, so
    // cycle 1808 (99975.168 us) still puts lasers 0-10 (up to 99998.208 us) into it but
    // lasers 11-15 (from 100000.512 us) into revolution 1.
    ASSERT_EQ(per_revolution_laser.size(), 2u);
    for (int b = 0; b < 16; ++b) {
        const std::size_t first = b <= 10 ? 1809u : 1808u;
        EXPECT_EQ(per_revolution_laser[0][b], first) << "laser " << b;
        EXPECT_EQ(per_revolution_laser[1][b], 3616u - first) << "laser " << b;
    }
}

TEST(SurveySensorPresets, BeamTableFromACsvNextToTheSurvey) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", kBoxRoom);
    write_beam_table_csv(dir / "os1.csv", ouster_os1_64());
    test::write_file(dir / "survey.yaml", R"(scene: room.yaml
scanner: {type: rotating, preset: ouster_os1_64, beam_table: os1.csv, duration_s: 0.01}
platform: {type: static}
)");
    const SurveySpec spec = load_survey_spec(dir / "survey.yaml");
    EXPECT_EQ(spec.range_max_m, 120.0) << "the OS1 data sheet's range";
    EXPECT_EQ(spec.range_min_m, 0.8);
    const auto* c = spec.scanner.config<RotatingScanner>();
    ASSERT_NE(c, nullptr);
    const RotatingScannerConfig want = ouster_os1_64();
    EXPECT_EQ(c->beam_elevations_deg, want.beam_elevations_deg);
    EXPECT_EQ(c->beam_azimuth_offsets_deg, want.beam_azimuth_offsets_deg);
    EXPECT_EQ(c->beam_time_offsets_s, want.beam_time_offsets_s);

    test::write_file(dir / "s2.yaml", R"(scene: room.yaml
scanner: {type: rotating, preset: velodyne_vlp16, range_min_m: 1, range_max_m: 50}
platform: {type: static}
)");
    const SurveySpec own = load_survey_spec(dir / "s2.yaml");
    EXPECT_EQ(own.range_min_m, 1.0) << "the survey's keys win over the preset's";
    EXPECT_EQ(own.range_max_m, 50.0);
    test::write_file(dir / "s3.yaml",
                     "scene: room.yaml\nscanner: {type: rotating, preset: "
                     "hdl64}\nplatform: {type: static}\n");
    EXPECT_EQ(load_survey_spec(dir / "s3.yaml").range_max_m,
              std::numeric_limits<double>::infinity());

    test::write_file(dir / "bad.csv", "elevation_deg\n1\nnope\n");
    test::write_file(dir / "survey.yaml", R"(scene: room.yaml
scanner: {type: rotating, beam_table: bad.csv}
platform: {type: static}
)");
    try {
        (void)load_survey_spec(dir / "survey.yaml");
        FAIL() << "accepted a bad beam table";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("scanner.beam_table: " + (dir / "bad.csv").string() +
                           ":3: column 1 (elevation_deg): expected a finite number, got 'nope'"),
                  std::string::npos)
            << msg;
    }
}

TEST(SurveySensorPresets, ConflictingBeamKeysAreErrors) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", kBoxRoom);
    test::write_file(dir / "t.csv", "elevation_deg\n0\n");
    auto error_of = [&](const std::string& scanner) {
        test::write_file(dir / "s.yaml",
                         "scene: room.yaml\nscanner: " + scanner + "\nplatform: {type: static}\n");
        try {
            (void)load_survey_spec(dir / "s.yaml");
        } catch (const ConfigError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(error_of("{type: rotating, beam_table: t.csv, beam_elevations_deg: [0]}")
                  .find("give beam_table or beam_elevations_deg, not both"),
              std::string::npos);
    EXPECT_NE(error_of("{type: rotating, azimuth_resolution_deg: 0.2, firing_period_s: 1e-4}")
                  .find("give azimuth_resolution_deg or firing_period_s, not both"),
              std::string::npos);
    EXPECT_NE(error_of("{type: rotating, beam_table: missing.csv}").find("file not found"),
              std::string::npos);
    EXPECT_NE(error_of("{type: rotating, preset: vlp32}")
                  .find("unknown preset (expected vlp16, hdl32, hdl64, os128, velodyne_vlp16"),
              std::string::npos);
    // A table's rows replace the preset's; the preset's clock stays.
    test::write_file(dir / "s.yaml",
                     "scene: room.yaml\nscanner: {type: rotating, preset: "
                     "velodyne_vlp16, beam_table: t.csv}\nplatform: {type: "
                     "static}\n");
    const SurveySpec spec = load_survey_spec(dir / "s.yaml");
    const auto* c = spec.scanner.config<RotatingScanner>();
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->beam_elevations_deg, std::vector<double>{0.0});
    EXPECT_TRUE(c->beam_time_offsets_s.empty());
    EXPECT_DOUBLE_EQ(c->firing_period_s, 55.296e-6);
}

}  // namespace
}  // namespace beamtrace
