// The physics block's beam exit diameter and echo-detection keys.
#include <gtest/gtest.h>

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "physics/physics_yaml_support.hpp"

namespace beamtrace {
namespace {

const std::string& kHead = test::kPhysicsSurveyHead;

TEST(PhysicsYamlBeamWaveform, ExitDiameterAndDetectionKeysAreRead) {
    const SurveySpec s = parse_survey_spec(kHead + R"(physics:
  beam: {divergence_mrad: 0.5, rings: 2, exit_diameter_m: 0.03}
  waveform: {pulse_fwhm_ns: 4, min_separation_m: 1.2, min_dip: 0.25}
)",
                                           "s.yaml");
    ASSERT_TRUE(s.physics.has_value());
    EXPECT_EQ(s.physics->beam.exit_diameter_m, 0.03);
    EXPECT_EQ(s.physics->waveform.min_separation_m, 1.2);
    EXPECT_EQ(s.physics->waveform.min_dip, 0.25);
    // Defaults: a point source, automatic separation (c FWHM / 4), a 10 % dip.
    const SurveySpec d = parse_survey_spec(kHead + "physics: {}\n", "s.yaml");
    EXPECT_EQ(d.physics->beam.exit_diameter_m, 0.0);
    EXPECT_LT(d.physics->waveform.min_separation_m, 0.0);
    EXPECT_EQ(d.physics->waveform.min_dip, 0.1);
}

TEST(PhysicsYamlBeamWaveform, BadValuesAreRefused) {
    for (const char* bad : {"beam: {exit_diameter_m: -1}", "waveform: {min_dip: 1.5}",
                            "waveform: {min_dip: x}", "beam: {exit_diam: 1}"}) {
        EXPECT_THROW((void)parse_survey_spec(kHead + "physics:\n  " + bad + "\n", "s.yaml"),
                     ConfigError)
            << bad;
    }
}

}  // namespace
}  // namespace beamtrace
