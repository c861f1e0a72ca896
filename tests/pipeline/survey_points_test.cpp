// The survey's points stage without physics: one point per hit pulse, in pulse order, placed at
// origin + axis * t in world coordinates, labelled with the hit part, after the points already
// in the block; the other fields keep their defaults.
#include "pipeline/detail/survey_points.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "beamtrace/scene/scene.hpp"
#include "pipeline/detail/survey_block.hpp"

namespace beamtrace::detail {
namespace {

/// Two parts: faces [0, 10) are part 0 (label 2, id 7), faces [10, 20) part 1 (label 6, id 9).
Scene two_parts() {
    Scene scene;
    scene.origin_m = {1000.0, 2000.0, 10.0};
    scene.parts.push_back(
        {.name = "ground", .first_face = 0, .face_count = 10, .label = 2, .part_id = 7});
    scene.parts.push_back(
        {.name = "house", .first_face = 10, .face_count = 10, .label = 6, .part_id = 9});
    return scene;
}

/// A block of `pulses` pulses whose even pulses hit (t = 2 + k, faces alternating between the
/// parts) and odd ones miss.
void fill_block(BlockWork& w, std::size_t pulses) {
    w.size_for(4096, pulses, 1, 1);
    w.pulses.time_s.resize(pulses);
    w.pulses.channel.resize(pulses);
    w.pulses.scanner.assign(pulses, 0);
    for (std::size_t k = 0; k < pulses; ++k) {
        w.pulses.time_s[k] = 100.0 + 0.5 * static_cast<double>(k);
        w.pulses.channel[k] = static_cast<std::uint16_t>(300 + k);
        // Without physics the beam is the pulse's ray.
        w.rays.set(k, {static_cast<double>(k), -1.0, 2.0}, {0.0, 0.6, -0.8}, 0.0, 1e9);
        w.scan_angle[k] = static_cast<float>(k) - 3.0f;
        if (k % 2 == 0) {
            w.hits.t[k] = 2.0f + static_cast<float>(k);
            w.hits.face[k] = k % 4 == 0 ? 3u : 12u;
        }
    }
}

TEST(SurveyPoints, OnePointPerHitInPulseOrderAfterThoseInTheBlock) {
    const Scene scene = two_parts();
    SurveyPoints stage;
    stage.scene = &scene;
    BlockWork w;
    const std::size_t pulses = 9;
    fill_block(w, pulses);
    BlockPoint earlier;
    earlier.pulse = 77;
    w.points.points.push_back(earlier);  // a point already there stays first
    stage.run(w);
    ASSERT_EQ(w.points.points.size(), 1u + (pulses + 1) / 2);
    EXPECT_EQ(w.points.points[0].pulse, 77u);
    const BlockPoint blank{};
    for (std::size_t i = 1; i < w.points.points.size(); ++i) {
        const BlockPoint& p = w.points.points[i];
        const std::size_t k = 2 * (i - 1);
        const double t = 2.0 + static_cast<double>(k);
        SCOPED_TRACE("pulse " + std::to_string(k));
        EXPECT_EQ(p.pulse, 4096u + k);
        EXPECT_EQ(p.x, static_cast<double>(k) + 0.0 * t + 1000.0);
        EXPECT_EQ(p.y, -1.0 + 0.6 * t + 2000.0);
        EXPECT_EQ(p.z, 2.0 + -0.8 * t + 10.0);
        EXPECT_EQ(p.gps_time, 100.0 + 0.5 * static_cast<double>(k));
        EXPECT_EQ(p.range_m, static_cast<float>(t));
        EXPECT_EQ(p.scan_angle_deg, static_cast<float>(k) - 3.0f);
        EXPECT_EQ(p.channel, 300 + k);
        EXPECT_EQ(p.user_data, static_cast<std::uint8_t>((300 + k) & 0xFFu));
        EXPECT_EQ(p.return_number, 1);
        EXPECT_EQ(p.number_of_returns, 1);
        const bool ground = k % 4 == 0;
        EXPECT_EQ(p.face, ground ? 3u : 12u);
        EXPECT_EQ(p.classification, ground ? 2 : 6);
        EXPECT_EQ(p.point_source_id, ground ? 7 : 9);
        // The fields the stage leaves alone here keep their defaults.
        EXPECT_EQ(p.intensity, 0);
        EXPECT_EQ(p.scanner_channel, 0);
        EXPECT_EQ(p.red, 0);
        EXPECT_EQ(p.nir, 0);
        EXPECT_EQ(p.incidence_deg, 0.0f);
        EXPECT_TRUE(std::isnan(p.echo_width_ns));
        EXPECT_EQ(p.weather, 0);
        EXPECT_EQ(p.instance_id, 0u);
        EXPECT_EQ(p.velocity_mps.x, blank.velocity_mps.x);
    }
}

TEST(SurveyPoints, HitsAloneGiveThePointsOfTheGeneralPathByteForByte) {
    const Scene scene = two_parts();
    SurveyPoints lean;  // nothing but the ray, hit and part: SurveyPoints::run_hits
    lean.scene = &scene;
    SurveyPoints general = lean;
    general.no_echo = true;  // the general path (run_pulses), which also lists the misses
    BlockWork a, b;
    fill_block(a, 203);
    for (std::size_t k = 0; k < 203; k += 3) {  // hits in both parts, in runs and alone
        a.hits.t[k] = 0.25f * static_cast<float>(k);
        a.hits.face[k] = k % 7 < 4 ? 19u : 0u;
    }
    fill_block(b, 203);
    b.hits = a.hits;
    lean.run(a);
    general.run(b);
    ASSERT_EQ(a.points.points.size(), b.points.points.size());
    EXPECT_TRUE(a.points.no_echo.empty());
    EXPECT_FALSE(b.points.no_echo.empty());
    for (std::size_t i = 0; i < a.points.points.size(); ++i) {
        SCOPED_TRACE("point " + std::to_string(i));
        EXPECT_EQ(std::memcmp(&a.points.points[i], &b.points.points[i], sizeof(BlockPoint)), 0);
    }
}

}  // namespace
}  // namespace beamtrace::detail
