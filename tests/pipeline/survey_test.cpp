// Surveys end to end: analytic geometry of the patterns on moving platforms, LAS output read back
// by our reader and by an independent one, determinism, and the documented examples.
#include "beamtrace/pipeline/survey.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/npy.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

using test::run_and_read;

constexpr const char* kRoom = test::kBoxRoom;

TEST(Survey, StaticRotatingScannerInABoxRoom) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", kRoom);
    const auto points = run_and_read(R"(scene: room.yaml
scanner: {type: rotating, preset: vlp16, duration_s: 0.2}
platform: {type: static, position_m: [1, 2, 0]}
output: {trajectory_rate_hz: 0}
)",
                                     dir);
    // VLP-16: 16 beams, 0.2 degree steps, 10 Hz: 16 x 1800 pulses per revolution, 2 revolutions.
    ASSERT_EQ(points.size(), 2u * 16u * 1800u) << "a closed room returns every pulse";
    std::map<int, std::size_t> per_revolution, per_beam;
    for (const auto& p : points) {
        const bool on_wall =
            std::abs(std::abs(p.x) - 10.0) < 2e-3 || std::abs(std::abs(p.y) - 10.0) < 2e-3;
        ASSERT_TRUE(on_wall) << p.x << " " << p.y << " "
                             << p.z;  // +/-15 degree beams never reach floor or ceiling
        ASSERT_EQ(p.classification, 6);
        ++per_revolution[static_cast<int>(std::floor(p.gps_time * 10.0))];
        // The point's height says its beam's elevation: the VLP-16 datasheet's for the beam in
        // user data (within 0.01 degrees: 1 mm quantisation at 8-16 m).
        constexpr double kVlp16ElevationDeg[16] = {-15, 1, -13, 3,  -11, 5,  -9, 7,
                                                   -7,  9, -5,  11, -3,  13, -1, 15};
        ASSERT_LT(p.user_data, 16);
        ++per_beam[p.user_data];
        const double horizontal = std::hypot(p.x - 1.0, p.y - 2.0);
        const double elevation_deg = std::atan2(p.z, horizontal) * 180.0 / std::numbers::pi;
        ASSERT_NEAR(elevation_deg, kVlp16ElevationDeg[p.user_data], 0.01)
            << "beam " << int{p.user_data};
    }
    for (const auto& [beam, n] : per_beam) {
        EXPECT_EQ(n, 2u * 1800u) << "beam " << beam;
    }
    EXPECT_EQ(per_beam.size(), 16u);
    ASSERT_EQ(per_revolution.size(), 2u);
    for (const auto& [rev, n] : per_revolution) {
        EXPECT_EQ(n, 16u * 1800u) << "revolution " << rev;
    }
}

TEST(Survey, LineScannerSwathSpacingAndMotionDistortion) {
    test::TempDir dir;
    test::write_file(dir / "plane.yaml",
                     "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 2000}\n");
    const double H = 300, v = 60, rate = 50, max_deg = 20;
    const auto points = run_and_read(R"(scene: plane.yaml
scanner: {type: line, pulse_rate_hz: 20000, scan_rate_hz: 50, scan_angle_max_deg: 20, waveform: sawtooth, duration_s: 1.0}
platform: {type: legs, speed_mps: 60, waypoints_m: [[-100, 0, 300], [200, 0, 300]]}
mount: {boresight_deg: [0, -90, 0]}
)",
                                     dir);
    ASSERT_EQ(points.size(), 20000u);
    double ymin = 1e9, ymax = -1e9;
    std::map<long, const LasPoint*> line_start;
    for (const auto& p : points) {
        ASSERT_NEAR(p.z, 0.0, 1e-3);
        // Constant velocity: the along-track position is the platform's at the pulse time (the
        // scan plane is perpendicular to the track), so the lines are skewed by v * dt.
        ASSERT_NEAR(p.x, -100.0 + v * p.gps_time, 2e-3) << p.gps_time;
        ymin = std::min(ymin, p.y);
        ymax = std::max(ymax, p.y);
        const long line = std::lround(std::floor(p.gps_time * rate + 1e-9));
        if (!line_start.count(line)) {
            line_start[line] = &p;
        }
        // LAS scan angle: positive to the right of the track (-y when flying +x).
        ASSERT_NEAR(p.scan_angle_deg, -std::atan2(p.y, H) * 180.0 / std::numbers::pi, 0.01);
    }
    const double half_swath = H * std::tan(max_deg * std::numbers::pi / 180.0);
    EXPECT_NEAR(ymax - ymin, 2.0 * half_swath, 2.0 * half_swath * 0.01) << "swath width";
    ASSERT_EQ(line_start.size(), 50u);
    for (long k = 1; k < 50; ++k) {
        EXPECT_NEAR(line_start[k]->x - line_start[k - 1]->x, v / rate, 1e-3) << "line spacing";
    }
}

TEST(Survey, ImageScannerWritesRangeAndLabelImages) {
    test::TempDir dir;
    test::write_file(dir / "room.yaml", kRoom);
    const auto points = run_and_read(R"(scene: room.yaml
scanner: {type: pinhole, width: 40, height: 30, hfov_deg: 60, vfov_deg: 40}
platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, -90, 0]}
)",
                                     dir);
    ASSERT_EQ(points.size(), 1200u);
    const NpyArray img = read_npy_f32(dir / "out" / "range.npy");
    ASSERT_EQ(img.shape, (std::vector<std::size_t>{30, 40}));
    // Pixel (row v, column u) looks along normalize(1, y_u, z_v) in the sensor frame (x the
    // optical axis), y_u and z_v running linearly from tan(fov/2) to -tan(fov/2) across the
    // image (image_sensor.hpp); pitched -90 degrees the axis points straight down at the floor
    // 5 m below, so the ray meets it at 5 / cos(angle off the axis) = 5 sqrt(1 + y_u^2 + z_v^2),
    // whichever way the image is turned about the axis. The range is a float32 hit distance:
    // rounding to float is 6e-8 relative and the float ray/plane arithmetic a few times that, so
    // 2e-6 relative is a wide margin yet catches a pixel's direction or range off by 1e-5.
    const double ty = std::tan(30.0 * std::numbers::pi / 180.0);
    const double tz = std::tan(20.0 * std::numbers::pi / 180.0);
    double worst = 0.0;
    for (std::size_t v = 0; v < 30; ++v) {
        for (std::size_t u = 0; u < 40; ++u) {
            const double y = ty * (1.0 - 2.0 * static_cast<double>(u) / 39.0);
            const double z = tz * (1.0 - 2.0 * static_cast<double>(v) / 29.0);
            const double want = 5.0 * std::sqrt(1.0 + y * y + z * z);
            const double got = img.data[v * 40 + u];
            ASSERT_NEAR(got, want, 2e-6 * want) << "row " << v << " column " << u;
            worst = std::fmax(worst, std::abs(got - want) / want);
        }
    }
    RecordProperty("worst_relative_range_error", std::to_string(worst));
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "labels.png"));
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "range.png"));
    for (const auto& p : points) {
        ASSERT_EQ(p.classification, 2);  // the floor's label
    }
}

TEST(Survey, SameBytesForAnyThreadCountAndChunking) {
    test::TempDir a, b;
    const std::string yaml = R"(scene: demo
scanner: {type: rotating, preset: hdl32, duration_s: 0.05}
platform: {type: legs, speed_mps: 10, waypoints_m: [[-10, -10, 2], [10, -10, 3]]}
)";
    (void)run_and_read(yaml + "output: {csv: true}\n", a, 1, 1 << 16);
    const auto points = run_and_read(yaml + "output: {csv: true}\n", b, 2, 5000);
    EXPECT_EQ(test::read_file(a / "out" / "points.las"), test::read_file(b / "out" / "points.las"));
    const std::string csv = test::read_file(b / "out" / "points.csv");
    EXPECT_EQ(csv, test::read_file(a / "out" / "points.csv"));
    EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')),
              points.size() + 1);
    EXPECT_EQ(csv.substr(0, csv.find('\n')),
              "x,y,z,gps_time,range_m,classification,point_source_id,beam,scan_angle_deg");
    EXPECT_EQ(test::read_file(a / "out" / "trajectory.csv"),
              test::read_file(b / "out" / "trajectory.csv"));
    EXPECT_EQ(test::read_file(a / "out" / "preview.png"),
              test::read_file(b / "out" / "preview.png"));
}

TEST(Survey, SurveyRaysAreTheRaysItTracesAndMaxPulsesStopsEarly) {
    test::TempDir dir;
    test::write_file(dir / "survey.yaml", R"(scene: demo
scanner: {type: rotating, preset: hdl32, duration_s: 0.1}
platform: {type: legs, speed_mps: 10, waypoints_m: [[-10, -10, 2], [10, -10, 3]]}
mount: {lever_arm_m: [0.5, 0, 0.3], boresight_deg: [1, 2, 3]}
)");
    const SurveySpec spec = load_survey_spec(dir / "survey.yaml");
    SurveyRunConfig run;
    run.output_dir = dir / "out";
    run.backend = BackendKind::bvh;
    run.max_pulses = 30000;
    const SurveyResult result = run_survey(spec, run);
    ASSERT_EQ(result.pulses, 30000u);
    ThreadPool pool(2);
    const RayBatch rays = survey_rays(spec, run.seed, run.max_pulses, pool);
    ASSERT_EQ(rays.size(), 30000u);
    const Scene scene = make_demo_scene();
    const HitBatch hits =
        make_backend(BackendKind::bvh, scene.geometry, pool)->intersect(rays, pool);
    const auto points = read_las_points(dir / "out" / "points.las");
    ASSERT_EQ(points.size(), result.points);
    std::size_t k = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!hits.hit(i)) {
            continue;
        }
        ASSERT_LT(k, points.size());
        const Vec3d p = rays.origin(i) + rays.direction(i) * double{hits.t[i]} + scene.origin_m;
        ASSERT_NEAR(points[k].x, p.x, 0.0006) << "ray " << i;
        ASSERT_NEAR(points[k].y, p.y, 0.0006) << "ray " << i;
        ASSERT_NEAR(points[k].z, p.z, 0.0006) << "ray " << i;
        ++k;
    }
    EXPECT_EQ(k, points.size());
    EXPECT_GT(k, rays.size() / 2);
}

TEST(Survey, FileErrorsAreListedWithLinesAndKeys) {
    test::TempDir dir;
    test::write_file(dir / "bad.yaml", R"(scene: nowhere.yaml
scanner: {type: rotating, preset: vlp99, rotation_rate_hz: -1}
platform: {type: legs, waypoints_m: [[0, 0, 0]]}
output: {point_format: 9, color: red}
)");
    try {
        (void)load_survey_spec(dir / "bad.yaml");
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const char* needle :
             {"bad.yaml:1: scene: file not found", "bad.yaml:2: scanner.preset: unknown preset",
              "scanner.rotation_rate_hz: must be positive", "bad.yaml:3: platform.waypoints_m",
              "bad.yaml:4: output.point_format", "output.color: unknown key"}) {
            EXPECT_NE(msg.find(needle), std::string::npos) << needle << "\n" << msg;
        }
    }
}

TEST(Survey, EachScannerTypeAcceptsOnlyItsOwnKeys) {
    // Keys of another type were silently ignored: a rotating scanner with a line scanner's
    // scan_rate_hz, a pinhole with a duration (an image scanner fires frames).
    test::TempDir dir;
    const std::pair<const char*, const char*> cases[] = {
        {"{type: rotating, preset: vlp16, scan_rate_hz: 50}",
         "s.yaml:2: scanner.scan_rate_hz: unknown key for a rotating scanner"},
        {"{type: fibre, preset: vlp16}",
         "s.yaml:2: scanner.preset: unknown key for a fibre scanner"},
        {"{type: line, preset: vlp16}",  // the line scanner has its own presets
         "s.yaml:2: scanner.preset: unknown preset (expected leica_als50_ii)"},
        {"{type: pinhole, width: 4, height: 4, duration_s: 2}",
         "s.yaml:2: scanner.duration_s: unknown key for a pinhole scanner"},
        {"{type: scan, width: 4, height: 4, rotation_rate_hz: 10}",
         "s.yaml:2: scanner.rotation_rate_hz: unknown key for a scan scanner"},
    };
    for (const auto& [scanner, expected] : cases) {
        test::write_file(dir / "s.yaml", std::string("scene: demo\nscanner: ") + scanner +
                                             "\nplatform: {type: static, position_m: [0, 0, 5]}\n");
        try {
            (void)load_survey_spec(dir / "s.yaml");
            ADD_FAILURE() << scanner << " was accepted";
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << scanner << "\n"
                                                                               << e.what();
        }
    }
}

TEST(Survey, TrajectoryShorterThanTheScanIsRefused) {
    test::TempDir dir;
    test::write_file(dir / "s.yaml", R"(scene: demo
scanner: {type: line, duration_s: 5}
platform: {type: legs, speed_mps: 50, waypoints_m: [[0, 0, 100], [100, 0, 100]]}
)");
    const SurveySpec spec = load_survey_spec(dir / "s.yaml");
    SurveyRunConfig run;
    run.output_dir = dir / "out";
    EXPECT_THROW((void)run_survey(spec, run), ConfigError);
    EXPECT_FALSE(std::filesystem::exists(dir / "out" / "points.las"));
}

/// Runs an example survey through the CLI and returns the output folder's LAS path.
std::filesystem::path run_example(const std::string& name, const test::TempDir& dir) {
    const auto r =
        test::run_command(std::string(BEAMTRACE_CLI_PATH) + " survey " + BEAMTRACE_EXAMPLES_DIR +
                          "/surveys/" + name + " --quiet --output " + dir.path().string());
    EXPECT_EQ(r.exit_code, 0) << r.out;
    return dir / "points.las";
}

TEST(SurveyExamples, SphereTargetPointsLieOnTheirSpheres) {
    // The tripod scan of six exact 0.1 m spheres (five in a row 8 m north, one 19 m away) with
    // 2 mm range noise: every target point is within 5 sigma of its sphere's surface, the near
    // targets get about a hundred points each, and the far one fewer.
    test::TempDir dir;
    const auto points = read_las_points(run_example("tripod_spheres.yaml", dir));
    std::vector<Vec3d> centres;
    for (int k = 0; k < 5; ++k) {
        centres.push_back({-8.0 + 4.0 * k, 8.0, 1.5});
    }
    centres.push_back({12.0, -15.0, 1.2});
    std::vector<int> per_target(centres.size(), 0);
    for (const auto& p : points) {
        if (p.classification != 64) {
            continue;
        }
        std::size_t best = 0;
        for (std::size_t k = 1; k < centres.size(); ++k) {
            if (length(Vec3d{p.x, p.y, p.z} - centres[k]) <
                length(Vec3d{p.x, p.y, p.z} - centres[best])) {
                best = k;
            }
        }
        EXPECT_NEAR(length(Vec3d{p.x, p.y, p.z} - centres[best]), 0.1, 0.011)
            << p.x << " " << p.y << " " << p.z;
        ++per_target[best];
    }
    for (std::size_t k = 0; k < 5; ++k) {
        EXPECT_GT(per_target[k], 40) << "target " << k;
        EXPECT_GT(per_target[k], per_target[5]) << "target " << k;
    }
    EXPECT_GT(per_target[5], 5);
}

}  // namespace
}  // namespace beamtrace
