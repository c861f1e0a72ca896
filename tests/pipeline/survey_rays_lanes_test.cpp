// The survey's rays without physics four pulses at a time (AVX2) against one at a time: the same
// doubles and scan angles, bit for bit, through runs of one attitude, attitude changes at any
// lane and an attitude that changes every pulse.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/detail/survey_rays.hpp"

namespace beamtrace::detail {
namespace {

/// A rotating scanner (16,000 pulses/s, every direction's components all non-zero) on legs
/// 1 m or 1.41 m long at 10 m/s (corners at pulses 1600, 3863, 5463), the mount levered and turned;
/// `attitudes`: extra platform keys (per-waypoint attitudes: one every pulse).
SurveySpec legs_survey(const std::string& attitudes) {
    return parse_survey_spec(R"(scene: demo
scanner: {type: rotating, beam_elevations_deg: [-15, -5, 5, 15], rotation_rate_hz: 10,
          azimuth_resolution_deg: 0.9, duration_s: 1.0}
platform:
  type: legs
  speed_mps: 10
  waypoints_m: [[0, 0, 100], [1, 0, 100], [1, 1, 101], [0, 1, 100], [0, 0, 99]]
)" + attitudes + R"(
mount: {lever_arm_m: [0.5, -0.2, 0.3], boresight_deg: [3, -80, 7]}
)",
                             "lanes.yaml");
}

std::uint64_t bits(double v) {
    return std::bit_cast<std::uint64_t>(v);
}

/// generate() of `count` pulses from `first` with and without lanes: equal bit for bit; the
/// beams asked for apart are the rays.
void expect_lanes_match(const SurveySpec& spec, std::uint64_t first, std::size_t count) {
    const auto pattern = spec.make_pattern();
    const auto trajectory = spec.make_trajectory();
    PulseBatch pulses;
    pattern->generate(first, count, pulses);
    SurveyRaySource lanes{&spec, trajectory.get(), nullptr, 1};
    SurveyRaySource scalar = lanes;
    scalar.lanes = false;
    RayBatch a, b;
    a.resize(count + 3);  // an offset into the batch
    b.resize(count + 3);
    std::vector<Vec3d> origin(count), axis(count);
    std::vector<float> angle_a(count), angle_b(count);
    SurveyRaySource::Scratch scratch;
    lanes.generate(pulses, first, a, 3, origin.data(), axis.data(), angle_a.data(), scratch);
    scalar.generate(pulses, first, b, 3, nullptr, nullptr, angle_b.data(), scratch);
    for (std::size_t i = 0; i < count; ++i) {
        SCOPED_TRACE("pulse " + std::to_string(first + i));
        const std::size_t r = i + 3;
        const double got[] = {a.ox[r], a.oy[r], a.oz[r],   a.dx[r],
                              a.dy[r], a.dz[r], a.tmin[r], a.tmax[r]};
        const double want[] = {b.ox[r], b.oy[r], b.oz[r],   b.dx[r],
                               b.dy[r], b.dz[r], b.tmin[r], b.tmax[r]};
        for (int c = 0; c < 8; ++c) {
            ASSERT_EQ(bits(got[c]), bits(want[c])) << "component " << c;
        }
        ASSERT_EQ(std::bit_cast<std::uint32_t>(angle_a[i]),
                  std::bit_cast<std::uint32_t>(angle_b[i]));
        ASSERT_EQ(bits(origin[i].x), bits(b.ox[r]));
        ASSERT_EQ(bits(origin[i].z), bits(b.oz[r]));
        ASSERT_EQ(bits(axis[i].y), bits(b.dy[r]));
        ASSERT_EQ(bits(axis[i].z), bits(b.dz[r]));
    }
}

TEST(SurveyRaysLanes, SameRaysAsOnePulseAtATimeAcrossCorners) {
    const SurveySpec spec = legs_survey("");
    // Blocks of odd sizes from odd starts: the corners at different lanes.
    for (const std::uint64_t first : {0u, 1597u, 3850u, 5000u}) {
        expect_lanes_match(spec, first, 1021);
    }
}

TEST(SurveyRaysLanes, SameRaysWhenTheAttitudeChangesEveryPulse) {
    const SurveySpec spec = legs_survey(
        "  attitudes_deg: [[0, 0, 0], [5, 2, 90], [-4, 1, 180], [2, -3, 270], [0, 0, 360]]");
    expect_lanes_match(spec, 0, 2050);
}

}  // namespace
}  // namespace beamtrace::detail
