// The survey file's `weather:` block: values, defaults and `file:line: weather.key: what` errors.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"

namespace beamtrace {
namespace {

const std::string kHead = R"(scene: demo
scanner: {type: rotating, preset: vlp16}
platform: {type: static, position_m: [0, 0, 2]}
physics: {}
)";

SurveySpec parse(const std::string& weather) {
    return parse_survey_spec(kHead + weather, "w.yaml");
}

std::string error_of(const std::string& weather) {
    try {
        (void)parse(weather);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

TEST(WeatherYaml, NoBlockIsClearAir) {
    EXPECT_FALSE(parse("").physics->weather.has_value());
}

TEST(WeatherYaml, FogRainAndSurfaces) {
    const SurveySpec s = parse(
        "weather:\n  fog: {mor_m: 50}\n  rain: {rate_mm_h: 25, particle_albedo: 0.05}\n"
        "  wetness: 0.8\n  overlap_start_m: 0.3\n  overlap_full_m: 1.2\n  medium_class: 18\n");
    ASSERT_TRUE(s.physics->weather.has_value());
    const WeatherConfig& w = *s.physics->weather;
    ASSERT_TRUE(w.fog.has_value());
    EXPECT_EQ(w.fog->mor_m, 50.0);
    EXPECT_NEAR(fog_extinction_per_m(*w.fog), std::log(20.0) / 50.0, 1e-15);
    ASSERT_TRUE(w.precipitation.has_value());
    EXPECT_EQ(w.precipitation->kind, PrecipitationKind::rain);
    EXPECT_EQ(w.precipitation->rate_mm_h, 25.0);
    EXPECT_EQ(w.precipitation->particle_albedo, 0.05);
    EXPECT_EQ(w.precipitation->floor_fraction, 0.5);  // the default
    EXPECT_EQ(w.wetness, 0.8);
    EXPECT_EQ(w.overlap.start_m, 0.3);
    EXPECT_EQ(w.overlap.full_m, 1.2);
    EXPECT_EQ(w.medium_class, 18);
    EXPECT_NEAR(weather_extinction_per_m(w),
                std::log(20.0) / 50.0 +
                    extinction_per_m(drop_size_distribution(PrecipitationKind::rain, 25.0)),
                1e-15);
}

TEST(WeatherYaml, SnowDefaults) {
    const SurveySpec s = parse("weather: {snow: {rate_mm_h: 2}, snow_cover: 1}\n");
    const WeatherConfig& w = *s.physics->weather;
    EXPECT_FALSE(w.fog.has_value());
    EXPECT_EQ(w.precipitation->kind, PrecipitationKind::snow);
    EXPECT_FALSE(w.precipitation->particle_albedo.has_value());
    EXPECT_EQ(w.snow_cover, 1.0);
    EXPECT_EQ(w.medium_class, 7);
    EXPECT_EQ(w.overlap.start_m, 0.5);
}

TEST(WeatherYaml, ErrorsNameTheLineAndKey) {
    EXPECT_NE(error_of("weather: {fog: {}}\n").find("w.yaml:5:"), std::string::npos);
    EXPECT_NE(error_of("weather: {fog: {}}\n").find("weather.fog.mor_m: missing"),
              std::string::npos);
    EXPECT_NE(error_of("weather: {fog: {mor_m: -3}}\n").find("weather.fog.mor_m: must be"),
              std::string::npos);
    EXPECT_NE(error_of("weather: {rain: {rate_mm_h: 0}}\n").find("weather.rain.rate_mm_h"),
              std::string::npos);
    EXPECT_NE(error_of("weather: {rain: {rate_mm_h: 5}, snow: {rate_mm_h: 1}}\n")
                  .find("weather.snow: give rain or snow, not both"),
              std::string::npos);
    EXPECT_NE(error_of("weather: {hail: 3}\n").find("hail"), std::string::npos);
    EXPECT_NE(error_of("weather: {wetness: 1.5}\n").find("weather.wetness: must be in [0, 1]"),
              std::string::npos);
    EXPECT_NE(error_of("weather: {overlap_start_m: 0}\n").find("weather.overlap_start_m"),
              std::string::npos);
    EXPECT_NE(error_of("weather: {snow: {rate_mm_h: x}}\n").find("weather.snow.rate_mm_h"),
              std::string::npos);
    EXPECT_NE(error_of("weather: 3\n").find("weather: expected a map"), std::string::npos);
    EXPECT_NE(error_of("weather: {fog: {mor_m: 0.5}}\n").find("weather.fog.mor_m: below 1 m"),
              std::string::npos);
    EXPECT_NE(error_of("weather: {fog: {mor_m: 9, backscatter_per_m_sr: 1e300}}\n")
                  .find("weather.fog.backscatter_per_m_sr: must be in [0, 10]"),
              std::string::npos);
}

}  // namespace
}  // namespace beamtrace
