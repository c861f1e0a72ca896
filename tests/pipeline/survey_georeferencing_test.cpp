// Georeferencing errors in a survey: the beam is traced from the true pose and the point placed
// with the measured one, so platform noise moves the points off the surface by the analytic
// amount (H sigma for attitude, sigma for position), calibration errors shift them, and the
// Gauss-Markov errors are the same at any thread count and block size.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "beamtrace/core/quat.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

using test::run_and_read;

constexpr double kHeight_m = 100.0;
constexpr double kDeg = std::numbers::pi / 180.0;

/// A static scanner `kHeight_m` above a flat floor, looking straight down, firing one pixel
/// `frames` times; `noise` is the physics.noise map.
std::string nadir_survey(int frames, const std::string& noise) {
    return R"(scene: floor.yaml
scanner: {type: pinhole, width: 1, height: 1, hfov_deg: 0.01, vfov_deg: 0.01, frames: )" +
           std::to_string(frames) + R"(}
platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, -90, 0]}
physics:
  atmosphere: {enabled: false}
  noise: )" +
           noise +
           R"(
output: {trajectory_rate_hz: 0}
)";
}

std::vector<LasPoint> run_nadir(int frames, const std::string& noise) {
    test::TempDir dir;
    test::write_file(dir / "floor.yaml", R"(parts:
  - {plane: {point_m: [0, 0, -100], normal: [0, 0, 1], size_m: 1000}}
)");
    return run_and_read(nadir_survey(frames, noise), dir);
}

struct Spread {
    double x = 0, y = 0, z = 0;  ///< standard deviations about (0, 0, -H)
};

Spread spread(const std::vector<LasPoint>& points) {
    Spread s;
    for (const auto& p : points) {
        s.x += p.x * p.x;
        s.y += p.y * p.y;
        s.z += (p.z + kHeight_m) * (p.z + kHeight_m);
    }
    const auto n = static_cast<double>(points.size());
    return {std::sqrt(s.x / n), std::sqrt(s.y / n), std::sqrt(s.z / n)};
}

// Acceptance: with the noise off every point lies on the floor, under the scanner.
TEST(SurveyGeoreferencing, WithoutErrorsPointsLieOnTheSurface) {
    const auto points = run_nadir(1000, "{range_sigma_m: 0}");
    ASSERT_EQ(points.size(), 1000u);
    for (const auto& p : points) {
        EXPECT_NEAR(p.z, -kHeight_m, 1e-3);
        EXPECT_NEAR(std::hypot(p.x, p.y), 0.0, 2e-3);
    }
}

// Acceptance: an attitude error sigma at height H gives horizontal point errors of std H sigma
// (within 3 % over 1e5 pulses); the vertical error is second order.
TEST(SurveyGeoreferencing, AttitudeNoiseMovesPointsByHeightTimesSigma) {
    const double sigma_deg = 0.01;
    const auto points = run_nadir(100'000, "{attitude_sigma_deg: 0.01}");
    ASSERT_EQ(points.size(), 100'000u);
    const Spread s = spread(points);
    const double want = kHeight_m * sigma_deg * kDeg;  // 1.75 cm
    EXPECT_NEAR(s.x, want, 0.03 * want);
    EXPECT_NEAR(s.y, want, 0.03 * want);
    EXPECT_LT(s.z, 2e-3);
}

// The beam is traced from the TRUE pose (range H whatever the error) and the point placed with
// the measured one: at a large attitude error sigma the points lie H from the scanner, on a
// sphere, E[H (1 - cos theta)] = H sigma^2 above the floor (two tilt axes). Tracing from the
// noisy pose would put them on the floor at ranges H / cos(theta).
TEST(SurveyGeoreferencing, RaysLeaveTheTruePoseAndPointsTheMeasuredOne) {
    const double sigma = 2.0 * kDeg;
    const auto points = run_nadir(20'000, "{attitude_sigma_deg: 2}");
    ASSERT_EQ(points.size(), 20'000u);
    double lift = 0;
    for (const auto& p : points) {
        EXPECT_NEAR(std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z), kHeight_m, 2e-3);
        lift += p.z + kHeight_m;
    }
    lift /= static_cast<double>(points.size());
    EXPECT_NEAR(lift, kHeight_m * sigma * sigma, 0.05 * kHeight_m * sigma * sigma);
}

// Acceptance: a position error sigma moves the points by sigma in x, y and z.
TEST(SurveyGeoreferencing, PositionNoiseMovesPointsBySigmaPerAxis) {
    const auto points = run_nadir(100'000, "{position_sigma_m: 0.05}");
    ASSERT_EQ(points.size(), 100'000u);
    const Spread s = spread(points);
    EXPECT_NEAR(s.x, 0.05, 0.03 * 0.05);
    EXPECT_NEAR(s.y, 0.05, 0.03 * 0.05);
    EXPECT_NEAR(s.z, 0.05, 0.03 * 0.05);
}

// Gauss-Markov errors reach the points: neighbouring pulses (1 us apart, tau = 10 ms) move
// together, while white errors of the same sigma differ by sqrt(2) sigma.
TEST(SurveyGeoreferencing, CorrelatedErrorsMoveNeighbouringPointsTogether) {
    const auto gm = run_nadir(20'000, "{position_sigma_m: 0.05, correlation_time_s: 0.01}");
    const auto white = run_nadir(20'000, "{position_sigma_m: 0.05}");
    ASSERT_EQ(gm.size(), 20'000u);
    ASSERT_EQ(white.size(), gm.size());
    double d_gm = 0, d_white = 0, var_gm = 0;
    for (std::size_t i = 1; i < gm.size(); ++i) {
        d_gm += std::pow(gm[i].x - gm[i - 1].x, 2);
        d_white += std::pow(white[i].x - white[i - 1].x, 2);
        var_gm += gm[i].x * gm[i].x + gm[i].y * gm[i].y + std::pow(gm[i].z + kHeight_m, 2);
    }
    const auto n = static_cast<double>(gm.size() - 1);
    EXPECT_NEAR(std::sqrt(d_white / n), std::sqrt(2.0) * 0.05, 0.05 * 0.05);
    EXPECT_LT(std::sqrt(d_gm / n), 2e-3);     // ~0.05 sqrt(2 * 1e-4 / tau * 8) ~ 1 mm at most
    EXPECT_GT(std::sqrt(var_gm / n), 0.005);  // and yet off the surface (3 axes)
}

// Acceptance: the lever-arm error shifts every point by the error turned into the world; a
// boresight error e tilts the measured beam: the point moves H sin(e) sideways and
// H (1 - cos(e)) up.
TEST(SurveyGeoreferencing, LeverArmAndBoresightErrorsShiftPointsAnalytically) {
    const auto lever = run_nadir(1, "{lever_arm_error_m: [0.1, -0.2, 0.3]}");
    ASSERT_EQ(lever.size(), 1u);
    const Vec3d shift = Quat::from_rpy({0, -90 * kDeg, 0}).rotate({0.1, -0.2, 0.3});
    EXPECT_NEAR(lever[0].x, shift.x, 1e-3);
    EXPECT_NEAR(lever[0].y, shift.y, 1e-3);
    EXPECT_NEAR(lever[0].z, -kHeight_m + shift.z, 1e-3);
    EXPECT_NEAR(std::abs(lever[0].z + kHeight_m), 0.1, 1e-3);  // body x points down
    for (const char* bore : {"[0, 0.5, 0]", "[0, 0, 0.5]"}) {
        const auto p = run_nadir(1, std::string("{boresight_error_deg: ") + bore + "}");
        ASSERT_EQ(p.size(), 1u);
        EXPECT_NEAR(std::hypot(p[0].x, p[0].y), kHeight_m * std::sin(0.5 * kDeg), 1e-3) << bore;
        EXPECT_NEAR(p[0].z, -kHeight_m * std::cos(0.5 * kDeg), 1e-3) << bore;
    }
    // Roll about the beam itself: nothing moves.
    const auto roll = run_nadir(1, "{boresight_error_deg: [0.5, 0, 0]}");
    EXPECT_NEAR(std::hypot(roll[0].x, roll[0].y), 0.0, 2e-3);
}

// Acceptance: a survey with every georeferencing error, Gauss-Markov in time, is byte-identical
// at 1 and 2 threads and at two block sizes.
TEST(SurveyGeoreferencing, GaussMarkovSurveyIsIdenticalForAnyThreadsAndBlocks) {
    const std::string yaml = R"(scene: demo
scanner: {type: rotating, preset: vlp16, duration_s: 0.05}
platform: {type: legs, speed_mps: 10, waypoints_m: [[-10, -10, 2], [10, -10, 3]]}
mount: {lever_arm_m: [0.2, 0, 0.5]}
physics:
  beam: {divergence_mrad: 1, rings: 1}
  noise: {position_sigma_m: 0.03, attitude_sigma_deg: 0.02, correlation_time_s: 0.004,
          lever_arm_error_m: [0.01, 0.02, -0.01], boresight_error_deg: [0.01, -0.02, 0.03]}
)";
    test::TempDir a, b, c;
    const auto pa = run_and_read(yaml, a, 1, 1 << 16);
    (void)run_and_read(yaml, b, 2, 777);
    (void)run_and_read(yaml, c, 2, 4096);
    ASSERT_GT(pa.size(), 1000u);
    const std::string las = test::read_file(a / "out" / "points.las");
    EXPECT_EQ(las, test::read_file(b / "out" / "points.las"));
    EXPECT_EQ(las, test::read_file(c / "out" / "points.las"));
}

}  // namespace
}  // namespace beamtrace
