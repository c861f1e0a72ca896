// Trajectories: interpolation (exact at samples, linear between, slerp), legs flown at constant
// speed, the yaw convention, mount composition, the trajectory CSV and its errors.
#include "beamtrace/sensor/trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

void expect_near(const Vec3d& a, const Vec3d& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

/// Same rotation: compare the images of the three axes.
void expect_same_rotation(const Quat& a, const Quat& b, double tol) {
    for (const Vec3d axis : {Vec3d{1, 0, 0}, Vec3d{0, 1, 0}, Vec3d{0, 0, 1}}) {
        expect_near(a.rotate(axis), b.rotate(axis), tol);
    }
}

SampledTrajectory three_samples() {
    return SampledTrajectory({{0.0, {0.0, 0.0, 100.0}, {0.0, 0.0, 0.0}},
                              {1.0, {10.0, -4.0, 102.0}, {0.1, -0.2, 0.3}},
                              {3.0, {30.0, 0.0, 98.0}, {-0.1, 0.05, 1.0}}});
}

TEST(Trajectory, SampledIsExactAtSamplesAndLinearInBetween) {
    const SampledTrajectory traj = three_samples();
    EXPECT_EQ(traj.start_time_s(), 0.0);
    EXPECT_EQ(traj.end_time_s(), 3.0);
    for (const auto& s : traj.samples()) {
        const Pose pose = traj.pose_at(s.time_s);
        EXPECT_EQ(pose.position_m, s.position_m);
        expect_same_rotation(pose.attitude, Quat::from_rpy(s.attitude), 1e-15);
    }
    expect_near(traj.pose_at(0.25).position_m, {2.5, -1.0, 100.5}, 1e-12);
    expect_near(traj.pose_at(2.0).position_m, {20.0, -2.0, 100.0}, 1e-12);
    for (double t = 1.0; t <= 3.0; t += 0.125) {  // linear: constant velocity within a segment
        const double f = (t - 1.0) / 2.0;
        expect_near(traj.pose_at(t).position_m,
                    Vec3d{10.0, -4.0, 102.0} + Vec3d{20.0, 4.0, -4.0} * f, 1e-12);
    }
}

TEST(Trajectory, SlerpHalfwayThroughANinetyDegreeYawIsFortyFive) {
    const SampledTrajectory traj(
        {{0.0, {0, 0, 0}, {0.0, 0.0, 0.0}}, {2.0, {0, 0, 0}, {0.0, 0.0, kPi / 2}}});
    const Pose half = traj.pose_at(1.0);
    expect_same_rotation(half.attitude, Quat::from_rpy({0.0, 0.0, kPi / 4}), 1e-15);
    EXPECT_NEAR(to_rpy(half.attitude).yaw_rad, kPi / 4, 1e-15);
    // Report's yaw: positive turns +x towards -y.
    expect_near(half.apply_direction({1, 0, 0}), {std::sqrt(0.5), -std::sqrt(0.5), 0}, 1e-15);
    EXPECT_NEAR(to_rpy(traj.pose_at(0.5).attitude).yaw_rad, kPi / 8, 1e-15);
}

TEST(Trajectory, OutsideTheTimeRangeThrowsButRoundingIsClamped) {
    const SampledTrajectory traj = three_samples();
    EXPECT_THROW(static_cast<void>(traj.pose_at(-0.01)), ConfigError);
    EXPECT_THROW(static_cast<void>(traj.pose_at(3.5)), ConfigError);
    EXPECT_THROW(static_cast<void>(traj.pose_at(std::nan(""))), ConfigError);
    EXPECT_EQ(traj.pose_at(3.0 + 1e-12).position_m, Vec3d(30.0, 0.0, 98.0));
    EXPECT_EQ(traj.pose_at(-1e-12).position_m, Vec3d(0.0, 0.0, 100.0));
    EXPECT_TRUE(traj.covers(0.0, 3.0));
    EXPECT_FALSE(traj.covers(0.0, 3.1));
}

TEST(Trajectory, SampledRejectsTimesThatDoNotIncreaseNamingTheRow) {
    try {
        SampledTrajectory traj({{0.0, {}, {}}, {1.0, {}, {}}, {1.0, {}, {}}});
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("sample 2"), std::string::npos) << e.what();
    }
    EXPECT_THROW(SampledTrajectory({}), ConfigError);
    EXPECT_THROW(SampledTrajectory({{0.0, {INFINITY, 0, 0}, {}}}), ConfigError);
    const SampledTrajectory single({{5.0, {1, 2, 3}, {}}});
    EXPECT_EQ(single.pose_at(5.0).position_m, Vec3d(1, 2, 3));
}

TEST(Trajectory, LinearLegsFlyAtConstantSpeedFacingAlongEachLeg) {
    const LinearLegs legs(
        {{{0, 0, 100}, {1000, 0, 100}, {1000, 500, 100}, {1000, 500, 200}}, {}, 50.0, 10.0});
    ASSERT_EQ(legs.waypoint_times_s(), (std::vector<double>{10.0, 30.0, 40.0, 42.0}));
    EXPECT_EQ(legs.start_time_s(), 10.0);
    EXPECT_EQ(legs.end_time_s(), 42.0);
    expect_near(legs.pose_at(20.0).position_m, {500, 0, 100}, 1e-12);
    expect_near(legs.pose_at(35.0).position_m, {1000, 250, 100}, 1e-12);
    EXPECT_EQ(legs.pose_at(42.0).position_m, Vec3d(1000, 500, 200));
    // A sensor with an identity mount looks along the leg, level.
    expect_near(legs.pose_at(15.0).apply_direction({1, 0, 0}), {1, 0, 0}, 1e-15);
    expect_near(legs.pose_at(15.0).apply_direction({0, 0, 1}), {0, 0, 1}, 1e-15);
    expect_near(legs.pose_at(35.0).apply_direction({1, 0, 0}), {0, 1, 0}, 1e-15);
    // In the report's convention that is yaw = atan2(-dy, dx) = -pi/2 for a leg along +y.
    EXPECT_NEAR(to_rpy(legs.pose_at(35.0).attitude).yaw_rad, -kPi / 2, 1e-15);
    // At a waypoint the next leg's heading applies; the vertical last leg keeps the heading.
    expect_near(legs.pose_at(30.0).apply_direction({1, 0, 0}), {0, 1, 0}, 1e-15);
    expect_near(legs.pose_at(41.0).apply_direction({1, 0, 0}), {0, 1, 0}, 1e-15);
    EXPECT_THROW(static_cast<void>(legs.pose_at(9.0)), ConfigError);
}

TEST(Trajectory, BatchedPosesEqualPoseAtBitForBit) {
    const LinearLegs legs(
        {{{0, 0, 100}, {1000, 0, 100}, {1000, 500, 100}, {1000, 500, 200}}, {}, 50.0, 10.0});
    const LinearLegs given(
        {{{0, 0, 0}, {100, 0, 0}, {100, 50, 0}},
         {RollPitchYaw{0, 0, 0}, RollPitchYaw{0, 0, kPi / 2}, RollPitchYaw{0.1, 0, kPi}},
         10.0,
         0.0});
    // Waypoints where a + (b - a) is not b: a leg's end is its end point, not the sum.
    const LinearLegs uneven(
        {{{1000.1, 4849000.123, -3.3}, {0.7, 123.456, 1.9}, {500000.37, -17.77, 0.7}},
         {},
         70.0,
         3.0});
    const SampledTrajectory sampled({{0.0, {0, 0, 0}, {}}, {2.0, {10, 0, 0}, {0, 0, 1}}});
    const StaticPlatform fixed({{1, 2, 3}, Quat::from_rpy({0.1, 0.2, 0.3})});
    for (const Trajectory* tr :
         std::initializer_list<const Trajectory*>{&legs, &given, &uneven, &sampled, &fixed}) {
        const double a = std::isfinite(tr->start_time_s()) ? tr->start_time_s() : 0.0;
        const double b = std::isfinite(tr->end_time_s()) ? tr->end_time_s() : 10.0;
        // Every waypoint time, times in between, out of order, and the ends.
        std::vector<double> times;
        for (int k = 0; k <= 997; ++k) {
            times.push_back(a + (b - a) * k / 997.0);
        }
        times.push_back(a);
        times.push_back(b);
        times.push_back(a + (b - a) * 0.5);
        std::vector<Pose> out(times.size()), scalar(times.size());
        tr->poses_at(times, out);
        // A linear flight's poses also one at a time (AVX2 lanes above where the CPU has them).
        const auto* linear = dynamic_cast<const LinearLegs*>(tr);
        if (linear != nullptr) {
            linear->poses_at_scalar(times, scalar);
        }
        for (std::size_t i = 0; i < times.size(); ++i) {
            const Pose want = tr->pose_at(times[i]);
            if (linear != nullptr) {
                ASSERT_EQ(scalar[i].position_m, want.position_m) << "t = " << times[i];
                ASSERT_EQ(scalar[i].attitude.w, want.attitude.w) << "t = " << times[i];
                ASSERT_EQ(scalar[i].attitude.z, want.attitude.z) << "t = " << times[i];
            }
            ASSERT_EQ(out[i].position_m, want.position_m) << "t = " << times[i];
            ASSERT_EQ(out[i].attitude.w, want.attitude.w) << "t = " << times[i];
            ASSERT_EQ(out[i].attitude.x, want.attitude.x);
            ASSERT_EQ(out[i].attitude.y, want.attitude.y);
            ASSERT_EQ(out[i].attitude.z, want.attitude.z);
        }
    }
    std::vector<Pose> out(1);
    const std::vector<double> late{43.0};
    EXPECT_THROW(legs.poses_at(late, out), ConfigError);
}

TEST(Trajectory, LinearLegsClimbingKeepsTheHeadingLevelAndSlerpsGivenAttitudes) {
    const LinearLegs climb({{{0, 0, 0}, {-30, -40, 50}}, {}, 10.0, 0.0});
    const Vec3d ahead = climb.pose_at(1.0).apply_direction({1, 0, 0});
    expect_near(ahead, {-0.6, -0.8, 0.0}, 1e-15);

    const LinearLegs given({{{0, 0, 0}, {100, 0, 0}},
                            {RollPitchYaw{0, 0, 0}, RollPitchYaw{0, 0, kPi / 2}},
                            10.0,
                            0.0});
    expect_same_rotation(given.pose_at(5.0).attitude, Quat::from_rpy({0, 0, kPi / 4}), 1e-15);
    expect_same_rotation(given.pose_at(10.0).attitude, Quat::from_rpy({0, 0, kPi / 2}), 1e-15);
}

TEST(Trajectory, LinearLegsValidationListsEveryProblem) {
    LinearLegsConfig c{{{0, 0, 0}, {0, 0, 0}}, {RollPitchYaw{}}, -1.0, std::nan("")};
    const auto problems = c.validate();
    EXPECT_EQ(problems.size(), 4u);
    EXPECT_THROW(LinearLegs{c}, ConfigError);
    EXPECT_FALSE(LinearLegsConfig{}.validate().empty());  // no waypoints
}

TEST(Trajectory, MountComposesLeverArmAndBoresight) {
    // Platform at (100, 50, 10) heading along world +y (report yaw -pi/2).
    const StaticPlatform platform({{100, 50, 10}, Quat::from_rpy({0, 0, -kPi / 2})});
    // Lever arm 2 m forward, 1 m down; boresight pitch -pi/2: sensor +x looks down.
    const Mount mount = Mount::from_lever_arm({2, 0, -1}, {0, -kPi / 2, 0});
    const Pose sensor = sensor_pose(platform, mount, 123.0);
    expect_near(sensor.apply_point({0, 0, 0}), {100, 52, 9}, 1e-12);
    expect_near(sensor.apply_direction({1, 0, 0}), {0, 0, -1}, 1e-15);  // optical axis: down
    expect_near(sensor.apply_direction({0, 0, 1}), {0, 1, 0}, 1e-15);   // sensor up: forward
    expect_near(sensor.apply_direction({0, 1, 0}), {-1, 0, 0}, 1e-15);  // sensor left: left
    // A point 10 m along the optical axis.
    expect_near(sensor.apply_point({10, 0, 0}), {100, 52, -1}, 1e-12);
}

TEST(Trajectory, ToRpyInvertsFromRpy) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> ang(-3.1, 3.1), half(-1.5, 1.5);
    for (int i = 0; i < 500; ++i) {
        const RollPitchYaw rpy{ang(rng), half(rng), ang(rng)};
        const RollPitchYaw back = to_rpy(Quat::from_rpy(rpy));
        EXPECT_NEAR(back.roll_rad, rpy.roll_rad, 1e-9);
        EXPECT_NEAR(back.pitch_rad, rpy.pitch_rad, 1e-9);
        EXPECT_NEAR(back.yaw_rad, rpy.yaw_rad, 1e-9);
    }
    // Gimbal lock: the rotation survives even though roll and yaw are not unique.
    const Quat locked = Quat::from_rpy({0.4, kPi / 2, 0.9});
    expect_same_rotation(Quat::from_rpy(to_rpy(locked)), locked, 1e-7);
}

class TrajectoryCsv : public test::TempDirTest {};

TEST_F(TrajectoryCsv, ReadsSamplesSkippingCommentsBlankLinesAndCrlf) {
    const auto path = write("t.csv",
                            "# survey 12\r\n time_s , x,y,z,roll,pitch,yaw\r\n\r\n"
                            "0.5, 1, 2, 3, 0.1, 0.2, 0.3\r\n# comment\n+1.5,4,5,6,0,0,-1e-3\n");
    const SampledTrajectory traj = read_trajectory_csv(path);
    ASSERT_EQ(traj.samples().size(), 2u);
    EXPECT_EQ(traj.samples()[0].time_s, 0.5);
    EXPECT_EQ(traj.samples()[0].position_m, Vec3d(1, 2, 3));
    EXPECT_EQ(traj.samples()[0].attitude.pitch_rad, 0.2);
    EXPECT_EQ(traj.samples()[1].time_s, 1.5);
    EXPECT_EQ(traj.samples()[1].attitude.yaw_rad, -1e-3);
}

TEST_F(TrajectoryCsv, WriteThenReadRoundTrips) {
    const SampledTrajectory traj = three_samples();
    const auto path = dir_ / "out.csv";
    write_trajectory_csv(path, traj, 8.0);  // every 0.125 s: hits every sample time
    const SampledTrajectory back = read_trajectory_csv(path);
    ASSERT_EQ(back.samples().size(), 25u);
    EXPECT_EQ(test::read_file(path).substr(0, 28), "time_s,x,y,z,roll,pitch,yaw\n");
    for (const auto& s : back.samples()) {
        const Pose expected = traj.pose_at(s.time_s);
        EXPECT_EQ(s.position_m, expected.position_m) << s.time_s;  // shortest round-trip text
        expect_same_rotation(Quat::from_rpy(s.attitude), expected.attitude, 1e-14);
    }
    for (const auto& s : traj.samples()) {
        EXPECT_EQ(back.pose_at(s.time_s).position_m, s.position_m);
    }
    // A rate that does not divide the range still ends exactly at the end time.
    write_trajectory_csv(path, traj, 3.0);
    const SampledTrajectory coarse = read_trajectory_csv(path);
    EXPECT_EQ(coarse.end_time_s(), 3.0);
    EXPECT_EQ(coarse.samples().size(), 10u);  // 0, 1/3, ..., 8/3, then 3
}

TEST_F(TrajectoryCsv, WriteRefusesInfiniteRangesAndBadRates) {
    const StaticPlatform forever({{0, 0, 0}, Quat::identity()});
    EXPECT_THROW(write_trajectory_csv(dir_ / "a.csv", forever, 10.0), ConfigError);
    EXPECT_THROW(write_trajectory_csv(dir_ / "b.csv", three_samples(), 0.0), ConfigError);
    EXPECT_FALSE(std::filesystem::exists(dir_ / "a.csv"));
    const StaticPlatform bounded({{1, 2, 3}, Quat::identity()}, 0.0, 1.0);
    write_trajectory_csv(dir_ / "c.csv", bounded, 2.0);
    EXPECT_EQ(read_trajectory_csv(dir_ / "c.csv").samples().size(), 3u);
}

TEST_F(TrajectoryCsv, ErrorsNameTheFileAndLine) {
    const std::string header = "time_s,x,y,z,roll,pitch,yaw\n";
    auto read = [](const std::filesystem::path& p) { return read_trajectory_csv(p); };
    test::expect_input_error(read, write("h.csv", "t,x,y,z,roll,pitch,yaw\n0,0,0,0,0,0,0\n"),
                             ":1: expected the header");
    test::expect_input_error(read, write("f.csv", header + "0,0,0,0,0,0,0\n1,2,3\n"),
                             ":3: expected 7 fields");
    test::expect_input_error(read, write("n.csv", header + "\n0,0,0,0,0,0,0\n1,0,abc,0,0,0,0\n"),
                             ":4: field 'y' is not a finite number: 'abc'");
    test::expect_input_error(read, write("i.csv", header + "0,0,0,0,0,0,nan\n"), ":2: field 'yaw'");
    test::expect_input_error(read, write("t.csv", header + "1,0,0,0,0,0,0\n# c\n1,0,0,0,0,0,0\n"),
                             ":4: time 1 is not after");
    test::expect_input_error(read, write("e.csv", ""), "empty trajectory file");
    test::expect_input_error(read, write("o.csv", header), "no trajectory samples");
    test::expect_input_error(read, dir_ / "missing.csv", "cannot open");
}

}  // namespace
}  // namespace beamtrace
