// The LAS scan angle of a survey point: the polynomial atan2 against std::atan2.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "pipeline/detail/survey_rays.hpp"

namespace beamtrace {
namespace {

TEST(ScanAngle, MatchesAtan2WithinAHundredthOfALasStep) {
    std::mt19937 rng(3);
    std::normal_distribution<double> g(0.0, 1.0);
    const Vec3d forward = normalize(Vec3d{1.0, 0.3, 0.0});
    const Vec3d right = normalize(cross(forward, Vec3d{0, 0, 1}));
    double worst = 0.0;
    for (int k = 0; k < 200000; ++k) {
        const Vec3d dir = normalize(Vec3d{g(rng), g(rng), g(rng)});
        const double want =
            std::clamp(std::atan2(dot(dir, right), -dir.z) * 180.0 / std::numbers::pi, -90.0, 90.0);
        const double got = detail::las_scan_angle_deg(dir, forward);
        worst = std::max(worst, std::fabs(got - want));
    }
    EXPECT_LT(worst, 0.006 / 100);  // float output: ~4e-6 degrees at 90
    // Straight down, sideways, level and up.
    EXPECT_EQ(detail::las_scan_angle_deg({0, 0, -1}, forward), 0.0f);
    EXPECT_NEAR(detail::las_scan_angle_deg(normalize(right - Vec3d{0, 0, 1}), forward), 45.0f,
                1e-5f);
    EXPECT_NEAR(detail::las_scan_angle_deg(normalize(Vec3d{0, 0, -1} - right), forward), -45.0f,
                1e-5f);
    EXPECT_EQ(detail::las_scan_angle_deg(right, forward), 90.0f);
    EXPECT_EQ(detail::las_scan_angle_deg(normalize(right * -1.0 + Vec3d{0, 0, 0.5}), forward),
              -90.0f);
    // Travelling straight up: the world x axis is "right".
    EXPECT_NEAR(detail::las_scan_angle_deg(normalize(Vec3d{1, 0, -1}), {0, 0, 1}), 45.0f, 1e-5f);
}

TEST(ScanAngle, BatchGivesTheSameFloatsAsOneAtATime) {
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0.0, 1.0);
    const Vec3d forward = normalize(Vec3d{0.2, -1.0, 0.1});
    const Vec3d right = normalize(cross(forward, Vec3d{0, 0, 1}));
    std::vector<Vec3d> dirs;
    for (int k = 0; k < 100000; ++k) {
        dirs.push_back(normalize(Vec3d{g(rng), g(rng), g(rng)}));
    }
    // An odd count (the last one alone). The edges: straight down, level (y of both signs, and 0),
    // up, along `right` exactly.
    for (const Vec3d& d :
         {Vec3d{0, 0, -1}, Vec3d{0, 0, 1}, Vec3d{0, 0, 0}, Vec3d{-0.0, -0.0, -0.0}, right,
          right * -1.0, forward, forward * -1.0, normalize(right - Vec3d{0, 0, 1}),
          normalize(Vec3d{0, 0, -1} - right), normalize(Vec3d{0.3, 0.4, -0.5})}) {
        dirs.push_back(d);
    }
    RayBatch rays;
    rays.resize(dirs.size() + 3);
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        rays.set(i + 3, Vec3d{}, dirs[i], 0.0, 1.0);
    }
    std::vector<float> got(dirs.size());
    detail::las_scan_angles_deg(rays, 3, dirs.size(), forward, got.data());
    for (std::size_t i = 0; i < dirs.size(); ++i) {
        const float want = detail::las_scan_angle_deg(dirs[i], forward);
        ASSERT_EQ(std::bit_cast<std::uint32_t>(got[i]), std::bit_cast<std::uint32_t>(want))
            << i << ": " << got[i] << " against " << want;
    }
}

}  // namespace
}  // namespace beamtrace
