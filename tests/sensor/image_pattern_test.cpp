// The report's pinhole and scan images as timed scan patterns: the same rays in the same order
// as cast_rays_pinhole / cast_rays_scan, with pulse times, frames and chunking.
#include "beamtrace/sensor/image_pattern.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/trajectory.hpp"
#include "sensor/scan_pattern_test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

ImagePatternConfig config(ImageProjection projection) {
    ImagePatternConfig c;
    c.projection = projection;
    c.image.width = 37;
    c.image.height = 23;
    c.image.hfov_rad = projection == ImageProjection::scan ? 2.0 * kPi : 1.2;
    c.image.vfov_rad = 0.7;
    c.image.orientation = {0.1, -0.3, 0.7};
    c.image.position_m = {5.0, -2.0, 30.0};
    c.pulse_rate_hz = 50'000.0;
    c.start_time_s = 12.0;
    return c;
}

TEST(ImagePattern, PinholeAndScanMatchTheReportsRaysBitForBitInTheirOrder) {
    for (const ImageProjection projection : {ImageProjection::pinhole, ImageProjection::scan}) {
        const ImagePatternConfig c = config(projection);
        const ImagePattern pattern(c);
        const RayBatch rays = projection == ImageProjection::scan ? cast_rays_scan(c.image)
                                                                  : cast_rays_pinhole(c.image);
        ASSERT_EQ(pattern.pulse_count(), rays.size());
        const PulseBatch p = test::all_pulses(pattern);
        for (int u = 0; u < c.image.width; ++u) {
            for (int v = 0; v < c.image.height; ++v) {
                const std::size_t i = ray_index(u, v, c.image.height);
                ASSERT_EQ(p.direction[i], rays.direction(i)) << u << "," << v;
                ASSERT_EQ(p.channel[i], v);
                ASSERT_EQ(p.time_s[i], 12.0 + static_cast<double>(i) / 50'000.0);
                const double half = 0.5 * c.image.hfov_rad;
                const double column = linspace_at(half, -half, c.image.width, u);
                const double expected =
                    projection == ImageProjection::scan
                        ? column
                        : std::atan(linspace_at(std::tan(half), -std::tan(half), c.image.width, u));
                ASSERT_NEAR(p.scan_angle_deg[i], expected * 180.0 / kPi, 1e-4);
            }
        }
        // Column 0 is the left (+y before the orientation): positive scan angle.
        EXPECT_GT(p.scan_angle_deg[0], 0.0f);
    }
}

TEST(ImagePattern, StaticPlatformWithIdentityMountReproducesTheReportsRays) {
    const ImagePatternConfig c = config(ImageProjection::pinhole);
    const ImagePattern pattern(c);
    const RayBatch rays = cast_rays_pinhole(c.image);
    const StaticPlatform platform({c.image.position_m, Quat::identity()});
    const PulseBatch p = test::all_pulses(pattern);
    for (std::size_t i = 0; i < p.size(); i += 11) {
        const Pose pose = sensor_pose(platform, Mount{}, p.time_s[i]);
        ASSERT_EQ(pose.apply_point({0.0, 0.0, 0.0}), rays.origin(i));
        ASSERT_EQ(pose.apply_direction(p.direction[i]), rays.direction(i));
    }
}

TEST(ImagePattern, FramesRepeatTheImageAndChunkingDoesNotMatter) {
    ImagePatternConfig c = config(ImageProjection::scan);
    c.frames = 3;
    const ImagePattern pattern(c);
    const std::size_t pixels = 37 * 23;
    ASSERT_EQ(pattern.pixels_per_frame(), pixels);
    ASSERT_EQ(pattern.pulse_count(), 3 * pixels);
    const PulseBatch whole = test::all_pulses(pattern);
    for (std::size_t i = 0; i < 2 * pixels; ++i) {
        ASSERT_EQ(whole.direction[i + pixels], whole.direction[i]);
        ASSERT_EQ(whole.channel[i + pixels], whole.channel[i]);
        ASSERT_NEAR(whole.time_s[i + pixels] - whole.time_s[i],
                    static_cast<double>(pixels) / 50'000.0, 1e-12);
    }
    test::expect_chunking_does_not_matter(pattern, {1, 22, 500});
}

TEST(ImagePattern, PushBroomIsAOneColumnPinholeOnAMovingPlatform) {
    // Appendix B.1: a 1-pixel-wide pinhole cast once per step of a moving platform.
    ImagePatternConfig c;
    c.image.width = 1;
    c.image.height = 64;
    c.image.vfov_rad = 0.8;
    c.image.hfov_rad = 0.01;
    c.pulse_rate_hz = 6400.0;  // 100 lines per second
    c.frames = 50;
    const ImagePattern pattern(c);
    const LinearLegs legs({{{0.0, 0.0, 10.0}, {100.0, 0.0, 10.0}}, {}, 20.0, 0.0});
    const PulseBatch p = test::all_pulses(pattern);
    for (std::size_t line = 0; line < 50; ++line) {
        const std::size_t i = line * 64;
        const Pose pose = sensor_pose(legs, Mount{}, p.time_s[i]);
        EXPECT_NEAR(pose.apply_point({0.0, 0.0, 0.0}).x, 20.0 * static_cast<double>(line) / 100.0,
                    1e-12);
        EXPECT_EQ(p.direction[i].y, 0.0);  // the single column is the optical axis' plane
    }
}

TEST(ImagePattern, ValidationListsEveryProblem) {
    ImagePatternConfig c;
    c.image.width = 0;
    c.image.height = 70'000;
    c.pulse_rate_hz = 0.0;
    c.frames = 0;
    c.start_time_s = std::nan("");
    const auto problems = c.validate();
    EXPECT_EQ(problems.size(), 5u);
    try {
        ImagePattern pattern(c);
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const char* key : {"width", "height", "pulse_rate_hz", "frames", "start_time_s"}) {
            EXPECT_NE(msg.find(key), std::string::npos) << msg;
        }
    }
    ImagePatternConfig wide = config(ImageProjection::pinhole);
    wide.image.hfov_rad = 4.0;  // a pinhole cannot see 180 degrees
    EXPECT_THROW(ImagePattern{wide}, ConfigError);
}

TEST(ImagePattern, OneFrameAboveThePixelLimitIsRefusedNamingTheSettingAndTheLimit) {
    ImagePatternConfig c = config(ImageProjection::scan);
    c.image.width = 40'000;
    c.image.height = 40'000;
    const auto problems = c.validate();
    ASSERT_EQ(problems.size(), 1u);
    EXPECT_EQ(problems[0],
              "width x height of one frame (40000 x 40000) must be at most 67108864 pixels, the "
              "limit of the range and label images");
    EXPECT_THROW(ImagePattern{c}, ConfigError);
    c.image.width = 8192;  // the limit itself
    c.image.height = 8192;
    EXPECT_TRUE(c.validate().empty());
    c.image.width = 40'000;  // several frames write no images
    c.image.height = 40'000;
    c.frames = 2;
    EXPECT_TRUE(c.validate().empty());
}

}  // namespace
}  // namespace beamtrace
