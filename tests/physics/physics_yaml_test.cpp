#include <gtest/gtest.h>

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "physics/physics_yaml_support.hpp"

namespace beamtrace {
namespace {

const std::string& kHead = test::kPhysicsSurveyHead;

TEST(PhysicsYaml, NoBlockMeansNoPhysics) {
    EXPECT_FALSE(parse_survey_spec(kHead, "s.yaml").physics.has_value());
}

TEST(PhysicsYaml, EveryKeyIsRead) {
    const SurveySpec s = parse_survey_spec(kHead + R"(physics:
  wavelength_nm: 905
  peak_power_w: 50
  aperture_diameter_m: 0.02
  system_efficiency: 0.5
  detection_threshold_w: 2.0e-9
  intensity: {reference_range_m: 5, scale: logarithmic}
  atmosphere: {visibility_km: 5, model: kruse}
  beam: {divergence_mrad: 3, rings: 1}
  noise: {range_sigma_m: 0.02, range_sigma_per_m: 1.0e-4, angle_jitter_mrad: 0.1,
          position_sigma_m: 0.03, attitude_sigma_deg: 0.01, dropout_probability: 0.05}
  waveform: {pulse_fwhm_ns: 5, bin_ns: 1, keep: true}
  returns: {mode: strongest, max: 3}
)",
                                           "s.yaml");
    ASSERT_TRUE(s.physics.has_value());
    const PhysicsConfig& p = *s.physics;
    EXPECT_EQ(p.radiometry.wavelength_nm, 905);
    EXPECT_EQ(p.radiometry.peak_power_w, 50);
    EXPECT_EQ(p.radiometry.aperture_diameter_m, 0.02);
    EXPECT_EQ(p.radiometry.system_efficiency, 0.5);
    EXPECT_EQ(p.radiometry.detection_threshold_w, 2e-9);
    EXPECT_EQ(p.radiometry.intensity_reference_range_m, 5);
    EXPECT_EQ(p.radiometry.intensity_scale, IntensityScale::logarithmic);
    EXPECT_EQ(p.atmosphere.visibility_km, 5);
    EXPECT_EQ(p.atmosphere.model, ExtinctionModel::kruse);
    EXPECT_DOUBLE_EQ(p.beam.divergence_rad, 3e-3);
    EXPECT_EQ(p.beam.rings, 1);
    EXPECT_EQ(p.noise.range_sigma_m, 0.02);
    EXPECT_EQ(p.noise.range_sigma_per_m, 1e-4);
    EXPECT_DOUBLE_EQ(p.noise.angle_jitter_rad, 1e-4);
    EXPECT_EQ(p.noise.georeferencing.position_sigma_m, 0.03);
    EXPECT_NEAR(p.noise.georeferencing.attitude_sigma_rad, 0.01 * 3.14159265358979 / 180, 1e-12);
    EXPECT_EQ(p.noise.dropout_probability, 0.05);
    EXPECT_EQ(p.waveform.pulse_fwhm_ns, 5);
    EXPECT_EQ(p.waveform.bin_ns, 1);
    EXPECT_TRUE(p.keep_waveform);
    EXPECT_EQ(p.return_mode, ReturnMode::strongest);
    EXPECT_EQ(p.max_returns, 3);
    // Empty block: the documented defaults.
    const SurveySpec d = parse_survey_spec(kHead + "physics: {}\n", "s.yaml");
    ASSERT_TRUE(d.physics.has_value());
    EXPECT_EQ(d.physics->radiometry.wavelength_nm, PhysicsConfig{}.radiometry.wavelength_nm);
    EXPECT_EQ(d.physics->max_returns, PhysicsConfig{}.max_returns);
}

TEST(PhysicsYaml, ErrorsNameLineAndKey) {
    try {
        (void)parse_survey_spec(kHead + R"(physics:
  wavelength_nm: blue
  colour: red
  atmosphere: {model: mie}
  beam: {rings: 2.5}
  noise: {range_sigma_m: -1}
  returns: {mode: second, max: 99}
  waveform: {keep: maybe}
)",
                                "bad.yaml");
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const char* needle :
             {"bad.yaml:5: physics.wavelength_nm: expected a number",
              "bad.yaml:6: physics.colour: unknown key", "bad.yaml:7: physics.atmosphere.model",
              "bad.yaml:8: physics.beam.rings: expected an integer",
              "physics: noise: range_sigma_m must be zero or positive",
              "bad.yaml:10: physics.returns.mode: unknown return mode",
              "bad.yaml:10: physics.returns.max", "bad.yaml:11: physics.waveform.keep"}) {
            EXPECT_NE(msg.find(needle), std::string::npos) << needle << "\n" << msg;
        }
    }
}

// The intensity reference range is `auto` (unset, for the survey's pilot) unless a number is
// given; the survey BRDF defaults to the normalised Phong lobe.
TEST(PhysicsYaml, ReferenceRangeAutoAndBrdf) {
    const auto parse = [](const std::string& block) {
        return *parse_survey_spec(kHead + block, "s.yaml").physics;
    };
    EXPECT_FALSE(parse("physics: {}\n").radiometry.intensity_reference_range_m.has_value());
    EXPECT_EQ(parse("physics: {}\n").brdf, Brdf::normalized_phong);
    EXPECT_FALSE(parse("physics: {intensity: {reference_range_m: auto}}\n")
                     .radiometry.intensity_reference_range_m.has_value());
    EXPECT_EQ(parse("physics: {intensity: {reference_range_m: 1200}}\n")
                  .radiometry.intensity_reference_range_m,
              1200.0);
    EXPECT_EQ(parse("physics: {brdf: phenomenological}\n").brdf, Brdf::phenomenological);
    for (const char* bad :
         {"physics: {brdf: glossy}\n", "physics: {intensity: {reference_range_m: sometimes}}\n",
          "physics: {intensity: {reference_range_m: -3}}\n"}) {
        EXPECT_THROW((void)parse(bad), ConfigError) << bad;
    }
}

}  // namespace
}  // namespace beamtrace
