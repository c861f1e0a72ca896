// The survey's face cache (issue 21) keeps a face's normal for the pulses of a block only while
// it holds: a still face's at every time, a moving face's at its pulse's time. A divergent beam
// looks down at a plate tilting about an axis through the point it meets; every pulse's
// intensity follows the cosine of the plate's tilt at that pulse's time (Lambertian, closed
// form), which a normal kept from an earlier pulse would not.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kTiltRate = 2.5;  ///< rad/s about +x, through the origin (the beam's target)

TEST(PhysicsSubRayMovingFace, IntensityFollowsTheTiltAtEachPulsesTime) {
    test::TempDir dir;
    // The plate's centre is off the beam so that the beam meets the inside of one triangle.
    test::write_file(dir / "plate.yaml",
                     "parts:\n"
                     "  - {plane: {point_m: [10, 20, 0], normal: [0, 0, 1], size_m: 100},\n"
                     "     motion: {spin: {axis: [1, 0, 0], rate_rad_s: " +
                         std::to_string(kTiltRate) + ", pivot_m: [0, 0, 0]}}}\n");
    // 40 pulses 10 ms apart (one block): the tilt grows from 0 to 0.975 rad.
    const auto points = test::run_and_read(R"(scene: plate.yaml
scanner: {type: pinhole, width: 1, height: 1, hfov_deg: 1, vfov_deg: 1, frames: 40,
          pulse_rate_hz: 100}
platform: {type: static, position_m: [0, 0, 10], rotate_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 1, rings: 1}
  atmosphere: {enabled: false}
  intensity: {reference_range_m: 10}
output: {trajectory_rate_hz: 0}
)",
                                           dir, 1);
    ASSERT_EQ(points.size(), 40u);
    double t_max = 0.0;
    for (const LasPoint& p : points) {
        // Albedo 0.5 at 10 m is half the full scale; L(i) = cos i, i the tilt.
        const double want = 0.5 * 65535.0 * std::cos(kTiltRate * p.gps_time);
        EXPECT_NEAR(p.intensity, want, 0.01 * want + 1.0) << "t = " << p.gps_time;
        t_max = std::max(t_max, p.gps_time);
    }
    EXPECT_GT(t_max, 0.35);
}

}  // namespace
}  // namespace beamtrace
