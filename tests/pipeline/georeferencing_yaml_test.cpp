// The georeferencing keys of the survey file's physics.noise section: read in their units, with
// the documented defaults, and every bad value reported with its line and key.
#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "physics/physics_yaml_support.hpp"

namespace beamtrace {
namespace {

const std::string& kHead = test::kPhysicsSurveyHead;

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(GeoreferencingYaml, EveryKeyIsReadInItsUnits) {
    const SurveySpec s = parse_survey_spec(kHead + R"(physics:
  noise: {position_sigma_m: 0.03, attitude_sigma_deg: 0.01, correlation_time_s: 5,
          lever_arm_error_m: [0.01, -0.02, 0.03], boresight_error_deg: [0.1, -0.2, 0.3]}
)",
                                           "s.yaml");
    ASSERT_TRUE(s.physics.has_value());
    const GeoreferencingConfig& g = s.physics->noise.georeferencing;
    EXPECT_EQ(g.position_sigma_m, 0.03);
    EXPECT_NEAR(g.attitude_sigma_rad, 0.01 * kDeg, 1e-15);
    EXPECT_EQ(g.correlation_time_s, 5);
    EXPECT_EQ(g.lever_arm_error_m, (Vec3d{0.01, -0.02, 0.03}));
    EXPECT_NEAR(g.boresight_error.roll_rad, 0.1 * kDeg, 1e-15);
    EXPECT_NEAR(g.boresight_error.pitch_rad, -0.2 * kDeg, 1e-15);
    EXPECT_NEAR(g.boresight_error.yaw_rad, 0.3 * kDeg, 1e-15);
    // Defaults: no error at all.
    const SurveySpec d = parse_survey_spec(kHead + "physics: {noise: {}}\n", "s.yaml");
    EXPECT_TRUE(d.physics->noise.georeferencing.none());
    EXPECT_EQ(d.physics->noise.georeferencing.correlation_time_s, 0.0);
}

TEST(GeoreferencingYaml, BadValuesNameLineAndKey) {
    try {
        (void)parse_survey_spec(kHead + R"(physics:
  noise:
    position_sigma_m: -0.1
    attitude_sigma_deg: .nan
    correlation_time_s: -2
    lever_arm_error_m: [0, 1]
    boresight_error_deg: [0, x, 0]
)",
                                "bad.yaml");
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const char* needle :
             {"physics: noise: position_sigma_m must be zero or positive",
              "bad.yaml:7: physics.noise.attitude_sigma_deg: expected a finite number",
              "physics: noise: correlation_time_s must be zero or positive",
              "bad.yaml:9: physics.noise.lever_arm_error_m: expected three numbers",
              "bad.yaml:10: physics.noise.boresight_error_deg[1]: expected a number"}) {
            EXPECT_NE(msg.find(needle), std::string::npos) << needle << "\n" << msg;
        }
    }
    try {
        (void)parse_survey_spec(kHead + "physics: {noise: {correlation_time_s: 1.0e-9}}\n",
                                "tiny.yaml");
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("correlation_time_s must be 0 (white) or at least"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace beamtrace
