// The georeferencing-error model: white and Gauss-Markov pose errors (statistics, independence of
// the chunking), the measured pose and the fixed lever-arm and boresight errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

#include "beamtrace/physics/georeferencing.hpp"
#include "beamtrace/physics/noise.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "physics/sample_stats.hpp"

namespace beamtrace {
namespace {

using Stats = test::SampleStats;

Stats stats(const std::vector<double>& v) {
    return test::sample_stats(v);
}

/// The errors of `n` pulses fired every `dt_s` from `t0_s`, in one block.
std::vector<PoseError> errors_of(const GeoreferencingConfig& c, std::size_t n, double dt_s,
                                 double t0_s = 0.0, std::uint64_t seed = 9) {
    std::vector<double> t(n);
    for (std::size_t i = 0; i < n; ++i) {
        t[i] = t0_s + dt_s * static_cast<double>(i);
    }
    std::vector<PoseError> e(n);
    PlatformErrorScratch scratch;
    platform_errors(c, seed, 0, t, e, scratch);
    return e;
}

// Acceptance: white errors (correlation_time_s = 0) have sigma per axis within 3 % over 5e4
// pulses, zero mean; the measured pose carries exactly them.
TEST(Georeferencing, WhiteErrorsHaveTheirSigmaPerAxis) {
    GeoreferencingConfig c;
    c.position_sigma_m = 0.05;
    c.attitude_sigma_rad = 2e-4;
    constexpr std::size_t kN = 50'000;
    const auto e = errors_of(c, kN, 1e-5);
    std::vector<double> dx, dz, roll, yaw;
    const Pose pose{{100, 200, 300}, Quat::from_rpy({0.1, -0.2, 0.3})};
    for (std::size_t i = 0; i < kN; ++i) {
        dx.push_back(e[i].position_m.x);
        dz.push_back(e[i].position_m.z);
        roll.push_back(e[i].attitude_rad.x);
        yaw.push_back(e[i].attitude_rad.z);
        if (i < 100) {
            const Pose m = measured_platform_pose(pose, e[i]);
            EXPECT_NEAR(m.position_m.x - 100, e[i].position_m.x, 1e-12);
            // The body-frame error rotation: pose^-1 * m, about 2 * its vector part.
            const Quat err = pose.attitude.conjugate() * m.attitude;
            EXPECT_NEAR(2 * err.x * (err.w < 0 ? -1 : 1), e[i].attitude_rad.x, 1e-9);
        }
    }
    EXPECT_NEAR(stats(dx).std, 0.05, 0.03 * 0.05);
    EXPECT_NEAR(stats(dz).std, 0.05, 0.03 * 0.05);
    EXPECT_NEAR(stats(dx).mean, 0.0, 4 * 0.05 / std::sqrt(kN));
    EXPECT_NEAR(stats(roll).std, 2e-4, 0.03 * 2e-4);
    EXPECT_NEAR(stats(yaw).std, 2e-4, 0.03 * 2e-4);
    // Neighbouring pulses are independent.
    double lag1 = 0;
    for (std::size_t i = 0; i + 1 < kN; ++i) {
        lag1 += dx[i] * dx[i + 1];
    }
    EXPECT_NEAR(lag1 / kN / (0.05 * 0.05), 0.0, 0.02);
    // Off: no error at all.
    for (const auto& z : errors_of(GeoreferencingConfig{}, 10, 1e-5)) {
        EXPECT_EQ(z.position_m, Vec3d{});
        EXPECT_EQ(z.attitude_rad, Vec3d{});
    }
}

// Acceptance: the Gauss-Markov process has variance sigma^2 (at nodes and between them) and a
// lag-tau autocorrelation of e^-1; with a lag of 3 tau, e^-3.
TEST(Georeferencing, GaussMarkovHasItsVarianceAndCorrelationTime) {
    GeoreferencingConfig c;
    c.position_sigma_m = 0.03;
    c.attitude_sigma_rad = 1e-4;
    c.correlation_time_s = 2.0;
    // 1e5 pulses 0.37 tau apart (0.37 tau = 2.96 grid steps: every fraction between nodes) and
    // the same shifted by tau and by 3 tau: 3 axes of ~1.85e4 independent correlation times.
    constexpr std::size_t kN = 100'000;
    const double dt = 0.37 * c.correlation_time_s;
    const auto e0 = errors_of(c, kN, dt, 0.0);
    const auto e1 = errors_of(c, kN, dt, c.correlation_time_s);
    const auto e3 = errors_of(c, kN, dt, 3 * c.correlation_time_s);
    double var = 0, att_var = 0, r1 = 0, r3 = 0;
    for (std::size_t i = 0; i < kN; ++i) {
        const Vec3d& p = e0[i].position_m;
        var += dot(p, p);
        att_var += dot(e0[i].attitude_rad, e0[i].attitude_rad);
        r1 += dot(p, e1[i].position_m);
        r3 += dot(p, e3[i].position_m);
    }
    const double n3 = 3.0 * kN;
    EXPECT_NEAR(std::sqrt(var / n3), 0.03, 0.03 * 0.03);
    EXPECT_NEAR(std::sqrt(att_var / n3), 1e-4, 0.03 * 1e-4);
    EXPECT_NEAR(r1 / var, std::exp(-1.0), 0.03);
    EXPECT_NEAR(r3 / var, std::exp(-3.0), 0.03);
    // Pulses much closer than tau barely differ: the error is correlated, not white.
    const auto dense = errors_of(c, 1000, 1e-4);
    EXPECT_LT(std::abs(dense[1].position_m.x - dense[0].position_m.x), 1e-3 * 0.03);
}

// Acceptance: the value at a time is the same whatever block the pulse falls in (bit for bit):
// one block, blocks of 1, 7 and 333 pulses, the sparse per-pulse path, one pulse at a time
// through PulseSimulator::measured_pose.
TEST(Georeferencing, GaussMarkovValueDoesNotDependOnTheBlocks) {
    GeoreferencingConfig c;
    c.position_sigma_m = 0.05;
    c.attitude_sigma_rad = 3e-4;
    c.correlation_time_s = 0.01;
    constexpr std::size_t kN = 5000;
    std::vector<double> t(kN);
    for (std::size_t i = 0; i < kN; ++i) {
        t[i] = 1234.5 + 1.1e-4 * static_cast<double>(i);
    }
    std::vector<PoseError> whole(kN);
    PlatformErrorScratch scratch;
    platform_errors(c, 3, 0, t, whole, scratch);
    for (const std::size_t block : {std::size_t{1}, std::size_t{7}, std::size_t{333}}) {
        std::vector<PoseError> parts(kN);
        PlatformErrorScratch s;
        for (std::size_t b = 0; b < kN; b += block) {
            const std::size_t n = std::min(block, kN - b);
            platform_errors(c, 3, b, std::span(t).subspan(b, n), std::span(parts).subspan(b, n), s);
        }
        EXPECT_EQ(std::memcmp(whole.data(), parts.data(), kN * sizeof(PoseError)), 0) << block;
    }
    // Out of order and sparse (every 97th pulse, reversed): the per-pulse path.
    std::vector<double> sparse;
    for (std::size_t i = kN; i-- > 0;) {
        if (i % 97 == 0) {
            sparse.push_back(t[i]);
        }
    }
    std::vector<PoseError> se(sparse.size());
    platform_errors(c, 3, 0, sparse, se, scratch);
    for (std::size_t k = 0; k < sparse.size(); ++k) {
        const std::size_t i = (kN - 1) / 97 * 97 - 97 * k;
        EXPECT_EQ(std::memcmp(&se[k], &whole[i], sizeof(PoseError)), 0) << i;
    }
    // Two pulses 100 s apart (80 000 grid steps: the per-pulse path) are still the same.
    const std::vector<double> far{t[100], t[100] + 100.0};
    std::vector<PoseError> fe(2), alone(1);
    platform_errors(c, 3, 100, far, fe, scratch);
    EXPECT_EQ(std::memcmp(&fe[0], &whole[100], sizeof(PoseError)), 0);
    platform_errors(c, 3, 7, std::span(far).subspan(1), alone, scratch);
    EXPECT_EQ(std::memcmp(&fe[1], &alone[0], sizeof(PoseError)), 0);
    // The single-pulse call of the simulator gives the same measured pose.
    PhysicsConfig pc;
    pc.noise.georeferencing = c;
    const PulseSimulator sim(pc);
    const Pose platform{{1, 2, 3}, Quat::from_rpy({0.01, 0.02, 0.03})};
    const Pose mount{{0.1, 0, -0.2}, Quat::from_rpy({0, -std::numbers::pi / 2, 0})};
    for (const std::size_t i : {std::size_t{0}, std::size_t{1}, std::size_t{2500}}) {
        const Pose a = sim.measured_pose(3, i, t[i], platform, mount);
        const Pose b = measured_sensor_pose(c, platform, mount, whole[i]);
        EXPECT_EQ(a.position_m, b.position_m);
        EXPECT_EQ(a.attitude.w, b.attitude.w);
        EXPECT_EQ(a.attitude.z, b.attitude.z);
    }
    // The grid node is its direct sum, whatever range it was evaluated in.
    const GaussMarkovGrid grid(0.05, 0.01, RngStream::gauss_markov_position);
    GaussMarkovCache cache;
    grid.fill(3, 100, 140, cache);
    EXPECT_EQ(grid.node(3, 120), cache.nodes[20]);
    // At a node, the process is the node itself.
    EXPECT_EQ(grid.at(3, 120 * grid.step_s(), cache), grid.node(3, 120));
}

// Acceptance: the lever-arm error moves the sensor by the error turned by the platform; the
// boresight error turns the measured beam by its angle.
TEST(Georeferencing, LeverArmAndBoresightErrorsAreAppliedAnalytically) {
    GeoreferencingConfig c;
    c.lever_arm_error_m = {0.1, -0.2, 0.05};
    const Pose platform{{10, 20, 30}, Quat::from_axis_angle({0, 0, 1}, std::numbers::pi / 2)};
    const Pose mount{{1, 0, 0}, Quat{}};
    const Pose m = measured_sensor_pose(c, platform, mount, PoseError{});
    // Yawed 90 degrees: body x is world y, body y is world -x.
    const Vec3d want{10 + 0.2, 20 + 1 + 0.1, 30 + 0.05};
    EXPECT_NEAR(m.position_m.x, want.x, 1e-12);
    EXPECT_NEAR(m.position_m.y, want.y, 1e-12);
    EXPECT_NEAR(m.position_m.z, want.z, 1e-12);
    // A boresight pitch error e tilts a nadir beam by e: a point at range H moves H sin(e).
    c = {};
    c.boresight_error = {0, 0.01, 0};
    const Pose down{{0, 0, 0}, Quat::from_rpy({0, -std::numbers::pi / 2, 0})};
    const Pose b = measured_sensor_pose(c, Pose{}, down, PoseError{});
    const Vec3d beam = b.attitude.rotate({1, 0, 0});
    const Vec3d nadir = down.attitude.rotate({1, 0, 0});
    EXPECT_NEAR(nadir.z, -1.0, 1e-12);
    EXPECT_NEAR(std::acos(dot(beam, nadir)), 0.01, 1e-12);
    // A roll error about the beam's own axis does not move it.
    c.boresight_error = {0.01, 0, 0};
    const Vec3d rolled =
        measured_sensor_pose(c, Pose{}, down, PoseError{}).attitude.rotate({1, 0, 0});
    EXPECT_NEAR(length(rolled - nadir), 0.0, 1e-12);
    EXPECT_FALSE(c.none());
    EXPECT_TRUE(c.no_random_error());
}

TEST(Georeferencing, ValidateReportsEveryProblem) {
    GeoreferencingConfig c;
    EXPECT_TRUE(c.validate().empty());
    EXPECT_TRUE(c.none());
    c.position_sigma_m = -1;
    c.attitude_sigma_rad = std::nan("");
    c.correlation_time_s = 1e-9;
    c.lever_arm_error_m = {0, std::numeric_limits<double>::infinity(), 0};
    c.boresight_error.yaw_rad = std::nan("");
    const auto p = c.validate();
    ASSERT_EQ(p.size(), 5u);
    EXPECT_NE(p[0].find("position_sigma_m"), std::string::npos);
    EXPECT_NE(p[2].find("correlation_time_s"), std::string::npos);
    EXPECT_NE(p[4].find("boresight"), std::string::npos);
    c = {};
    c.correlation_time_s = -1;
    EXPECT_EQ(c.validate().size(), 1u);
    // Through the physics config: the simulator refuses it.
    PhysicsConfig pc;
    pc.noise.georeferencing.position_sigma_m = -0.1;
    EXPECT_FALSE(pc.validate().empty());
}

}  // namespace
}  // namespace beamtrace
