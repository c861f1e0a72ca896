// A smooth plane seen at steep incidence from far away gives one (broadened) return per pulse:
// the sub-rays' echoes, stretched by their footprint cells, no longer split into bumps.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(SurveyEchoSplit, SteepPlaneAtOneKilometreGivesOneReturnPerPulse) {
    test::TempDir dir;
    // The plane through (0, 0, -1000) whose normal is 83 deg from the vertical.
    const double inc = 83.0 * std::numbers::pi / 180.0;
    test::write_file(dir / "slope.yaml", "parts:\n  - {plane: {point_m: [0, 0, -1000], normal: [" +
                                             std::to_string(std::sin(inc)) + ", 0, " +
                                             std::to_string(std::cos(inc)) +
                                             "], size_m: 40000}, label: 2}\n");
    // A line scanner looking down, +-1 deg across the track: incidence 83 deg (82-84 deg).
    const auto points = test::run_and_read(R"(scene: slope.yaml
scanner: {type: line, pulse_rate_hz: 4000, scan_rate_hz: 10, scan_angle_max_deg: 1,
          waveform: triangle, duration_s: 0.5}
platform: {type: static, position_m: [0, 0, 0]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 0.5, rings: 2}
  detection_threshold_w: 1.0e-12
  atmosphere: {enabled: false}
  returns: {mode: all, max: 5}
output: {trajectory_rate_hz: 0}
)",
                                           dir);
    ASSERT_GT(points.size(), 1900u);
    std::size_t split = 0;
    for (const auto& p : points) {
        split += p.number_of_returns > 1 ? 1 : 0;
        EXPECT_NEAR(p.z, -1000.0 - p.x * std::tan(inc), 2.0);  // on the plane
    }
    EXPECT_EQ(split, 0u) << "pulses with more than one return";
}

}  // namespace
}  // namespace beamtrace
