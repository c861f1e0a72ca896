// Pulse length, power and detection threshold in the units data sheets use (docs/physics.md):
// HELIOS++'s pulse length as the FWHM of its pulse shape, pulse energy as the peak power of a
// Gaussian pulse, and a "range at reflectivity" figure as the detection threshold, checked
// against brute-force integrals, the range equation written out, and a survey at the quoted
// range.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/physics/range_equation.hpp"
#include "beamtrace/physics/waveform.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "physics/physics_yaml_support.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

const std::string& kHead = test::kPhysicsSurveyHead;

SurveySpec parse(const std::string& physics) {
    return parse_survey_spec(kHead + "physics:\n" + physics, "s.yaml");
}

std::string error_of(const std::string& physics) {
    try {
        (void)parse(physics);
        return "";
    } catch (const ConfigError& e) {
        return e.what();
    }
}

TEST(DataSheetUnits, HeliosPulseLengthIsItsShapesFwhm) {
    // HELIOS++'s pulse (t/tau)^2 exp(-t/tau), tau = L / 7: the half-maximum crossings by brute
    // force on a fine grid.
    const double length = 10.0, tau = length / 7.0;
    const auto p = [&](double t) { return (t / tau) * (t / tau) * std::exp(-t / tau); };
    const double peak = p(2.0 * tau);
    const int n = 2'000'000;
    double first = -1, last = -1;
    for (int i = 0; i <= n; ++i) {
        const double t = length * i / n;
        if (p(t) >= peak / 2) {
            first = first < 0 ? t : first;
            last = t;
        }
    }
    EXPECT_NEAR(last - first, helios_pulse_fwhm_ns(length), 2e-5);
    EXPECT_NEAR(helios_pulse_fwhm_ns(10.0), 4.8495, 1e-4);
}

TEST(DataSheetUnits, PulseEnergyIsTheGaussianPulsesIntegral) {
    const double fwhm = 5.0, energy = 20e-6;  // 20 uJ
    const double peak = gaussian_pulse_peak_power_w(energy, fwhm);
    // Integrate the Gaussian of that peak and FWHM (in seconds) by the midpoint rule.
    const double sigma_s = fwhm * 1e-9 / (2.0 * std::sqrt(2.0 * std::numbers::ln2));
    double sum = 0;
    const int n = 200'000;
    const double span = 16 * sigma_s, dt = span / n;
    for (int i = 0; i < n; ++i) {
        const double t = -span / 2 + (i + 0.5) * dt;
        sum += peak * std::exp(-t * t / (2 * sigma_s * sigma_s)) * dt;
    }
    EXPECT_NEAR(sum / energy, 1.0, 1e-9);
    EXPECT_NEAR(peak, 3757.8, 0.1);  // 20 uJ in 5 ns: 3.76 kW
}

TEST(DataSheetUnits, SurveyKeysMapOntoThePhysicsConfig) {
    const SurveySpec s = parse(
        "  waveform: {pulse_length_ns: 10}\n  pulse_energy_uj: 20\n  atmosphere: {enabled: "
        "false}\n  aperture_diameter_m: 0.1\n  system_efficiency: 0.5\n"
        "  detection: {range_m: 260, reflectance: 0.8}\n");
    ASSERT_TRUE(s.physics.has_value());
    EXPECT_NEAR(s.physics->waveform.pulse_fwhm_ns, 4.8495, 1e-4);
    const double peak =
        20e-6 / (4.84954381549500e-9 * std::sqrt(std::numbers::pi / 4 / std::log(2)));
    EXPECT_NEAR(s.physics->radiometry.peak_power_w, peak, 1e-9 * peak);
    // The range equation written out: P_t rho (pi D^2 / 4) / (pi R^2) eta, in vacuum.
    const double pr =
        peak * 0.8 * (std::numbers::pi * 0.01 / 4) / (std::numbers::pi * 260 * 260) * 0.5;
    EXPECT_NEAR(s.physics->radiometry.detection_threshold_w, pr, 1e-12 * pr);
    // With air: the two-way transmission at the quoted range lowers it by exp(-2 alpha R).
    const SurveySpec a = parse("  detection: {range_m: 1000, reflectance: 0.2}\n");
    RadiometryConfig r;
    const double alpha = extinction_per_m(AtmosphereConfig{}, r.wavelength_nm);
    ASSERT_GT(alpha, 0.0);
    EXPECT_NEAR(a.physics->radiometry.detection_threshold_w,
                threshold_for_detection_range_w(r, 1000, 0.2, 1.0) * std::exp(-2 * alpha * 1000),
                1e-15);
    // The old keys keep working.
    const SurveySpec o = parse(
        "  peak_power_w: 500\n  detection_threshold_w: 2e-9\n"
        "  waveform: {pulse_fwhm_ns: 3}\n");
    EXPECT_EQ(o.physics->radiometry.peak_power_w, 500.0);
    EXPECT_EQ(o.physics->radiometry.detection_threshold_w, 2e-9);
    EXPECT_EQ(o.physics->waveform.pulse_fwhm_ns, 3.0);
}

TEST(DataSheetUnits, OneKeyPerQuantity) {
    const struct {
        const char* physics;
        const char* message;
    } cases[] = {
        {"  waveform: {pulse_length_ns: 10, pulse_fwhm_ns: 4}\n",
         "physics.waveform.pulse_length_ns: give pulse_fwhm_ns or pulse_length_ns"},
        {"  peak_power_w: 1000\n  pulse_energy_uj: 20\n",
         "physics.pulse_energy_uj: give peak_power_w or pulse_energy_uj, not both"},
        {"  detection_threshold_w: 1e-9\n  detection: {range_m: 100, reflectance: 0.5}\n",
         "physics.detection: give detection_threshold_w or detection, not both"},
        {"  detection: {range_m: 100}\n", "physics.detection: missing reflectance"},
        {"  detection: {range_m: 100, reflectance: 1.5}\n",
         "physics.detection.reflectance: must be in (0, 1]"},
        {"  pulse_energy_uj: -3\n", "physics.pulse_energy_uj: must be positive"},
        {"  detection: {range_m: 100, reflectance: 0.5, visibility_km: 3}\n",
         "physics.detection.visibility_km: unknown key"},
    };
    for (const auto& c : cases) {
        const std::string e = error_of(c.physics);
        EXPECT_NE(e.find(c.message), std::string::npos) << c.physics << "\n" << e;
        EXPECT_NE(e.find("s.yaml:"), std::string::npos) << e;
    }
}

/// Points a nadir pinhole ray gets from a plane of albedo 0.8 `depth_m` below, with the
/// threshold set by "100 m at 80 %".
std::size_t points_at(double depth_m) {
    test::TempDir dir;
    test::write_file(dir / "plane.yaml",
                     "materials: [{name: grey, reflectance: 0.8}]\n"
                     "parts: [{plane: {point_m: [0, 0, " +
                         std::to_string(-depth_m) +
                         "], normal: [0, 0, 1], size_m: 50}, material: grey}]\n");
    return test::run_and_read(
               "scene: plane.yaml\n"
               "scanner: {type: pinhole, width: 1, height: 1, hfov_deg: 1, vfov_deg: 1}\n"
               "platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, -90, 0]}\n"
               "physics:\n  atmosphere: {enabled: false}\n"
               "  detection: {range_m: 100, reflectance: 0.8}\n"
               "output: {trajectory_rate_hz: 0}\n",
               dir, 1)
        .size();
}

TEST(DataSheetUnits, TheQuotedRangeIsTheDetectionLimit) {
    EXPECT_EQ(points_at(95.0), 1u);
    EXPECT_EQ(points_at(105.0), 0u);
}

}  // namespace
}  // namespace beamtrace
