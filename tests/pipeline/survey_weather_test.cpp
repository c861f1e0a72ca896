// Surveys in fog, rain and snow: the weather's points are classified as the medium's, lie in
// front of the scene, and the files are the same at any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "survey_test_support.hpp"

namespace beamtrace {
namespace {

/// A VLP-16 in the middle of the box room, 0.2 s, with a divergent beam.
std::string room_survey(const std::string& weather) {
    return std::string(R"(scene: room.yaml
scanner: {type: rotating, preset: vlp16, duration_s: 0.05}
platform: {type: static, position_m: [0, 0, 0]}
physics:
  wavelength_nm: 905
  peak_power_w: 50
  beam: {divergence_mrad: 3, rings: 1, exit_diameter_m: 0.01}
)") + weather;
}

std::vector<LasPoint> run(const std::string& weather, const test::TempDir& dir, unsigned threads,
                          std::size_t chunk = 1 << 16) {
    test::write_file(dir / "room.yaml", test::kBoxRoom);
    return test::run_and_read(room_survey(weather), dir, threads, chunk);
}

double distance_m(const LasPoint& p) {
    return std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
}

TEST(SurveyWeather, FogPointsAreClassifiedAndNearTheSensor) {
    test::TempDir clear_dir, fog_dir;
    const auto clear = run("", clear_dir, 2);
    const auto fog = run("weather: {fog: {mor_m: 40}}\n", fog_dir, 2);
    std::size_t medium = 0, walls = 0;
    for (const LasPoint& p : fog) {
        if (p.classification == 7) {
            ++medium;
            EXPECT_LT(distance_m(p), 9.0);  // the walls are 10 m or more away
        } else {
            ++walls;
            EXPECT_GE(distance_m(p), 4.99);  // the floor and ceiling are 5 m away
        }
    }
    EXPECT_GT(medium, fog.size() / 10);
    EXPECT_GT(walls, clear.size() / 2);
    for (const LasPoint& p : clear) {
        EXPECT_NE(p.classification, 7);
    }
}

TEST(SurveyWeather, EveryEffectGivesTheSameFileAtAnyThreadCount) {
    const std::string weather =
        "weather:\n  fog: {mor_m: 150}\n  rain: {rate_mm_h: 30}\n  wetness: 0.7\n";
    test::TempDir one, two;
    const auto a = run(weather, one, 1, 4096);
    const auto b = run(weather, two, 2);
    ASSERT_GT(a.size(), 1000u);
    EXPECT_EQ(test::read_file(one.path() / "out" / "points.las"),
              test::read_file(two.path() / "out" / "points.las"));
    std::size_t rain = 0;
    for (const LasPoint& p : a) {
        rain += p.classification == 7 ? 1 : 0;
    }
    EXPECT_GT(rain, 0u);
}

TEST(SurveyWeather, AMediumTooDenseForParticlesRunsOnFogAlone) {
    // MOR 1 m: nothing comes back from beyond the overlap ramp, so no snow particle is drawn
    // (a sampler over an empty range once threw an internal error here).
    test::TempDir dir;
    const auto points = run("weather: {fog: {mor_m: 1}, snow: {rate_mm_h: 400}}\n", dir, 2);
    ASSERT_FALSE(points.empty());
    for (const LasPoint& p : points) {
        EXPECT_EQ(p.classification, 7);  // the fog's echo only
    }
}

TEST(SurveyWeather, WetSurfacesAreDarker) {
    test::TempDir dry_dir, wet_dir;
    const auto dry = run("", dry_dir, 2);
    const auto wet = run("weather: {wetness: 1}\n", wet_dir, 2);
    ASSERT_EQ(dry.size(), wet.size());  // no medium: the same points
    double dry_sum = 0, wet_sum = 0;
    for (std::size_t i = 0; i < dry.size(); ++i) {
        EXPECT_EQ(dry[i].x, wet[i].x);
        dry_sum += dry[i].intensity;
        wet_sum += wet[i].intensity;
    }
    // The room's default material (albedo 0.5) wet: 0.339 / 0.5 of the power.
    EXPECT_NEAR(wet_sum / dry_sum, 0.339 / 0.5, 0.01);
}

}  // namespace
}  // namespace beamtrace
