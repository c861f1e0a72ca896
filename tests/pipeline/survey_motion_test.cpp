// Moving parts in a survey (docs/scene-file.md, `motion:`): a box sliding toward a static
// scanner is met where it is at each point's GPS time (x = x0 + v t within 1 mm), its points
// carry its velocity and instance ID as LAS extra bytes, the output is byte-identical at 1 and 2
// threads, and the two examples with moving parts run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "beamtrace/io/las_extra_bytes.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

constexpr double kSpeed = 5.0;       ///< m/s along +x, toward the scanner
constexpr double kFrontAt0 = -38.0;  ///< x of the box's leading face at time 0
constexpr double kWallX = -100.0;    ///< the still wall behind it

/// A 4 m cube (its leading face at x = +2 in its own coordinates) as an OBJ file.
void write_cube(const fs::path& path) {
    test::write_file(path,
                     "v -2 -2 -2\nv 2 -2 -2\nv 2 2 -2\nv -2 2 -2\n"
                     "v -2 -2 2\nv 2 -2 2\nv 2 2 2\nv -2 2 2\n"
                     "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                     "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n");
}

/// The scene (a still wall, then the sliding cube, `rows` copies 5 m apart along y, centred) and
/// a pinhole looking along -x from the origin, firing `frames` frames of 21 x 21 pulses at 2 kHz.
void write_survey(const test::TempDir& dir, int frames = 20, int rows = 1) {
    write_cube(dir / "cube.obj");
    test::write_file(dir / "scene.yaml",
                     "parts:\n"
                     "  - {name: box, mesh: cube.obj, transform: {translate_m: [" +
                         std::to_string(kFrontAt0 - 2.0) + ", " +
                         std::to_string(-2.5 * (rows - 1)) + ", 0]},\n     array: {count: [1, " +
                         std::to_string(rows) + ", 1], step_m: [0, 5, 0]},\n" +
                         "     motion: {velocity_mps: [" + std::to_string(kSpeed) +
                         ", 0, 0]}}\n"
                         "  - {name: wall, plane: {point_m: [" +
                         std::to_string(kWallX) + ", 0, 0], normal: [1, 0, 0], size_m: 200}}\n");
    test::write_file(
        dir / "survey.yaml",
        "scene: scene.yaml\n"
        "scanner: {type: pinhole, width: 21, height: 21, hfov_deg: 20, vfov_deg: 20,\n"
        "          frames: " +
            std::to_string(frames) +
            ", pulse_rate_hz: 2000}\n"
            "platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, 0, 180]}\n"
            "output: {trajectory_rate_hz: 0, extra_bytes: [instance_id, velocity_x, "
            "velocity_y, velocity_z]}\n");
}

void run(const test::TempDir& dir, const fs::path& out, unsigned threads) {
    const SurveySpec spec = load_survey_spec(dir / "survey.yaml");
    SurveyRunConfig config;
    config.output_dir = out;
    config.threads = threads;
    config.chunk_pulses = 1000;
    (void)run_survey(spec, config);
}

TEST(SurveyMotion, ASlidingBoxIsMetWhereItIsAtEachPointsTimeWithItsVelocity) {
    test::TempDir dir;
    write_survey(dir);
    run(dir, dir / "out", 2);
    const fs::path las = dir / "out" / "points.las";
    LasReader reader(las);
    const auto fields = las_extra_bytes_descriptors(reader.vlrs());
    ASSERT_EQ(fields.size(), 4u);
    EXPECT_EQ(fields[0].name, "instance_id");
    EXPECT_EQ(fields[1].name, "velocity_x");
    EXPECT_EQ(fields[1].data_type, LasExtraType::f32);
    const auto points = read_las_points(las);
    ASSERT_EQ(points.size(), 21u * 21u * 20u) << "every pulse meets the box or the wall";
    std::size_t front = 0, wall = 0;
    double t_min = 1e9, t_max = -1e9;
    for (const LasPoint& p : points) {
        const double id = las_extra_bytes_value(fields, 0, p.extra_bytes);
        const Vec3d v{las_extra_bytes_value(fields, 1, p.extra_bytes),
                      las_extra_bytes_value(fields, 2, p.extra_bytes),
                      las_extra_bytes_value(fields, 3, p.extra_bytes)};
        if (std::abs(p.x - kWallX) < 1e-3) {
            ++wall;
            EXPECT_EQ(id, 0.0) << "the wall is object 0 (still parts come first)";
            EXPECT_EQ(v, (Vec3d{0, 0, 0}));
            continue;
        }
        // Every other point lies on the box's leading face where it is at the point's time.
        ASSERT_NEAR(p.x, kFrontAt0 + kSpeed * p.gps_time, 1e-3) << "t = " << p.gps_time;
        EXPECT_EQ(id, 1.0);
        EXPECT_EQ(v, (Vec3d{kSpeed, 0, 0}));
        ++front;
        t_min = std::min(t_min, p.gps_time);
        t_max = std::max(t_max, p.gps_time);
    }
    EXPECT_GT(front, 1000u);
    EXPECT_GT(wall, 1000u);
    EXPECT_LT(t_min, 0.1);
    EXPECT_GT(t_max, 4.0) << "the box has moved 20 m by the last frame";
}

TEST(SurveyMotion, OutputsAreByteIdenticalAtOneAndTwoThreads) {
    test::TempDir dir;
    write_survey(dir, 200, 5);  // 88 200 pulses: 87 blocks, the two threads overlap
    run(dir, dir / "t1", 1);
    run(dir, dir / "t2", 2);
    const std::string one = test::read_file(dir / "t1" / "points.las");
    EXPECT_GT(one.size(), 100000u);
    EXPECT_TRUE(one == test::read_file(dir / "t2" / "points.las"));
}

TEST(SurveyMotion, ASceneOfMovingPartsOnlyGivesItsPointsInTheLasBounds) {
    test::TempDir dir;
    write_survey(dir);
    write_cube(dir / "cube.obj");
    test::write_file(dir / "scene.yaml",
                     "parts: [{mesh: cube.obj, transform: {translate_m: [-40, 0, 0]},\n"
                     "         motion: {velocity_mps: [5, 0, 0]}}]\n");
    run(dir, dir / "out", 2);
    const fs::path las = dir / "out" / "points.las";
    const LasHeader h = LasReader(las).header();
    const auto points = read_las_points(las);
    ASSERT_GT(points.size(), 1000u);
    for (const LasPoint& p : points) {
        ASSERT_NEAR(p.x, kFrontAt0 + kSpeed * p.gps_time, 1e-3);
        ASSERT_GE(p.x, h.min.x);
        ASSERT_LE(p.x, h.max.x);
    }
    // The offset is near the box's path (the bounds hold the moving part over the survey).
    EXPECT_GT(h.offset.x, -60.0);
    EXPECT_LT(h.offset.x, 0.0);
}

/// Blocks race if a block's moving frame (its top level, the rays shifted into a group) is not
/// its own: 87 blocks of three kinds of moving parts (a run of copies sharing a motion, a lone
/// sliding cube, a spinning one) at 1, 2 and 4 threads (thrice) give the same bytes, and every
/// point is on the surface of a cube placed (by its motion, worked out here) at the point's GPS
/// time, with that cube's velocity there.
TEST(SurveyMotion, ManyBlocksAtOneTwoAndFourThreadsAreIdenticalAndOnTheirPartsAtEachPointsTime) {
    test::TempDir dir;
    write_cube(dir / "cube.obj");
    test::write_file(dir / "scene.yaml",
                     "parts:\n"
                     "  - {mesh: cube.obj, transform: {translate_m: [-40, -5, 0]},\n"
                     "     array: {count: [1, 3, 1], step_m: [0, 5, 0]},\n"
                     "     motion: {velocity_mps: [5, 0, 0]}}\n"
                     "  - {mesh: cube.obj, transform: {translate_m: [-60, 3, 5]},\n"
                     "     motion: {velocity_mps: [2, -1, 0]}}\n"
                     "  - {mesh: cube.obj, transform: {translate_m: [-70, -4, -5]},\n"
                     "     motion: {spin: {axis: [0, 0, 1], rate_rad_s: 2}}}\n"
                     "  - {plane: {point_m: [-100, 0, 0], normal: [1, 0, 0], size_m: 200}}\n");
    test::write_file(dir / "survey.yaml",
                     "scene: scene.yaml\n"
                     "scanner: {type: pinhole, width: 21, height: 21, hfov_deg: 20, vfov_deg: 20,\n"
                     "          frames: 200, pulse_rate_hz: 20000}\n"
                     "platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, 0, 180]}\n"
                     "output: {trajectory_rate_hz: 0, extra_bytes: [velocity_x, velocity_y]}\n");
    const SurveySpec spec = load_survey_spec(dir / "survey.yaml");
    // Four threads thrice: a race shows in some runs only.
    const unsigned thread_counts[] = {1, 2, 4, 4, 4};
    for (std::size_t run = 0; run < std::size(thread_counts); ++run) {
        SurveyRunConfig config;
        config.output_dir = dir / ("run" + std::to_string(run));
        config.threads = thread_counts[run];
        config.chunk_pulses = 8192;  // 8 blocks in flight: the threads overlap
        (void)run_survey(spec, config);
    }
    const std::string one = test::read_file(dir / "run0" / "points.las");
    for (std::size_t run = 1; run < std::size(thread_counts); ++run) {
        EXPECT_TRUE(one == test::read_file(dir / ("run" + std::to_string(run)) / "points.las"))
            << thread_counts[run] << " threads, run " << run;
    }
    const auto points = read_las_points(dir / "run4" / "points.las");
    ASSERT_EQ(points.size(), 21u * 21u * 200u) << "every pulse meets a cube or the wall";
    LasReader reader(dir / "run4" / "points.las");
    const auto fields = las_extra_bytes_descriptors(reader.vlrs());
    std::size_t on[3] = {0, 0, 0};
    for (const LasPoint& p : points) {
        if (std::abs(p.x + 100.0) < 1e-3) {
            continue;  // the wall
        }
        const double t = p.gps_time;
        const Vec3d at{p.x, p.y, p.z};
        const Vec3d v{las_extra_bytes_value(fields, 0, p.extra_bytes),
                      las_extra_bytes_value(fields, 1, p.extra_bytes), 0.0};
        // Each cube's centre at t and the point in its own coordinates (turned back for the
        // spinning one): on its surface, the largest coordinate is +-2 m.
        const double a = 2.0 * t;
        const Vec3d spun = at - Vec3d{-70, -4, -5};
        const Vec3d in_spun{std::cos(a) * spun.x + std::sin(a) * spun.y,
                            -std::sin(a) * spun.x + std::cos(a) * spun.y, spun.z};
        const auto on_surface = [](const Vec3d& q) {
            const double m = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
            return std::abs(m - 2.0) < 1e-3;
        };
        bool found = false;
        for (int k = 0; k < 3 && !found; ++k) {
            found = on_surface(at - Vec3d{-40 + 5 * t, -5.0 + 5 * k, 0});
            if (found) {
                EXPECT_NEAR(v.x, 5.0, 1e-4);
                EXPECT_NEAR(v.y, 0.0, 1e-4);
                ++on[0];
            }
        }
        if (!found && on_surface(at - Vec3d{-60 + 2 * t, 3 - t, 5})) {
            found = true;
            EXPECT_NEAR(v.x, 2.0, 1e-4);
            EXPECT_NEAR(v.y, -1.0, 1e-4);
            ++on[1];
        }
        if (!found && on_surface(in_spun)) {
            found = true;
            // omega x r, omega = 2 z; r from the LAS coordinates (1 mm steps)
            EXPECT_NEAR(v.x, -2.0 * spun.y, 3e-3);
            EXPECT_NEAR(v.y, 2.0 * spun.x, 3e-3);
            ++on[2];
        }
        ASSERT_TRUE(found) << "a point on no cube at t = " << t << ": " << p.x << " " << p.y << " "
                           << p.z;
    }
    EXPECT_GT(on[0], 5000u);
    EXPECT_GT(on[1], 1000u);
    EXPECT_GT(on[2], 1000u);
}

/// The examples with moving parts, run small (max_pulses) from their own folder.
TEST(SurveyMotion, TheMovingExamplesRun) {
    for (const char* name : {"moving_cars_vlp16.yaml", "wind_turbine_als.yaml"}) {
        SCOPED_TRACE(name);
        test::TempDir dir;
        const SurveySpec spec =
            load_survey_spec(fs::path(BEAMTRACE_EXAMPLES_DIR) / "surveys" / name);
        SurveyRunConfig config;
        config.output_dir = dir / "out";
        config.threads = 2;
        config.max_pulses = 40000;
        const SurveyResult r = run_survey(spec, config);
        EXPECT_EQ(r.pulses, 40000u);
        const auto points = read_las_points(dir / "out" / "points.las");
        ASSERT_GT(points.size(), 1000u);
        LasReader reader(dir / "out" / "points.las");
        const auto fields = las_extra_bytes_descriptors(reader.vlrs());
        ASSERT_GE(fields.size(), 4u);
        // Some points are on a moving part: an instance with a non-zero velocity.
        std::size_t moving = 0;
        for (const LasPoint& p : points) {
            const double vx = las_extra_bytes_value(fields, 1, p.extra_bytes);
            const double vy = las_extra_bytes_value(fields, 2, p.extra_bytes);
            const double vz = las_extra_bytes_value(fields, 3, p.extra_bytes);
            moving += (vx != 0 || vy != 0 || vz != 0) ? 1 : 0;
        }
        EXPECT_GT(moving, 50u);
    }
}

}  // namespace
}  // namespace beamtrace
