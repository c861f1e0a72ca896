// Presets of the single-beam mechanisms (Livox Mid-40 / Avia, RIEGL VUX-1UAV / VQ-880-G /
// VQ-840-G, Leica ALS50-II): their parameters equal the values docs/sensors.md documents, the
// pattern properties the data sheets state hold for the generated directions, and a survey's own
// keys override a preset's (scanner, range limits and physics defaults).
#include "beamtrace/sensor/mechanism_presets.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "sensor/scan_pattern_test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

/// The largest angle between sensor +x and a pulse's direction, in degrees.
double max_off_axis_deg(const PulseBatch& p) {
    double m = 0.0;
    for (const Vec3d& d : p.direction) {
        m = std::max(m, std::acos(std::clamp(d.x, -1.0, 1.0)) * kRadToDeg);
    }
    return m;
}

SurveySpec parse(const std::string& scanner, const std::string& rest = "") {
    return parse_survey_spec(
        "scene: demo\nscanner: " + scanner + "\nplatform: {type: static}\n" + rest, "s.yaml");
}

TEST(MechanismPresets, ParametersEqualTheDocumentedValues) {
    const RisleyScannerConfig mid40 = livox_mid40();
    EXPECT_EQ(mid40.pulse_rate_hz, 100000.0);
    EXPECT_EQ(mid40.refractive_index, 1.509);
    EXPECT_NEAR(4.0 * mid40.prism_deviation_rad() * kRadToDeg, 38.4, 1e-12);
    EXPECT_NEAR(mid40.rotation_rate_1_hz, 121.5667, 1e-4);  // 7294 rpm
    EXPECT_NEAR(mid40.rotation_rate_2_hz, -77.7333, 1e-4);  // -4664 rpm
    const RisleyScannerConfig avia = livox_avia();
    EXPECT_EQ(avia.pulse_rate_hz, 240000.0);
    EXPECT_NEAR(4.0 * avia.prism_deviation_rad() * kRadToDeg, 70.4, 1e-12);

    const PolygonScannerConfig vux = riegl_vux1uav();
    EXPECT_EQ(vux.pulse_rate_hz, 500000.0);
    EXPECT_EQ(vux.facets, 2);
    EXPECT_EQ(vux.rotation_rate_hz, 100.0);
    EXPECT_NEAR(vux.usable_fraction * 360.0, 330.0, 1e-12);

    const ConicScannerConfig vq = riegl_vq880g();
    EXPECT_EQ(vq.pulse_rate_hz, 700000.0);
    EXPECT_EQ(vq.rotation_rate_hz, 80.0);
    EXPECT_EQ(vq.off_axis_deg, 20.0);
    const ConicScannerConfig vq840 = riegl_vq840g();
    EXPECT_EQ(vq840.pulse_rate_hz, 200000.0);
    EXPECT_EQ(vq840.rotation_rate_hz, 100.0);
    EXPECT_EQ(vq840.off_axis_deg, 20.0);

    const LineScannerConfig als = leica_als50_ii();
    EXPECT_EQ(als.pulse_rate_hz, 150000.0);
    EXPECT_EQ(als.scan_rate_hz, 90.0);
    EXPECT_EQ(als.scan_angle_max_deg, 37.5);
    EXPECT_EQ(als.waveform, ScanWaveform::triangle);

    // The data sheets' facts (docs/sensors.md's table).
    const double livox_div = 0.28 / kRadToDeg * 1e3;
    const auto sheet = [](auto presets, std::string_view name) {
        const auto* p = find_mechanism_preset(presets, name);
        EXPECT_NE(p, nullptr) << name;
        return p != nullptr ? p->sheet : SensorDataSheet{};
    };
    const SensorDataSheet m = sheet(risley_presets(), "livox_mid40");
    EXPECT_EQ(m.range_max_m, 260.0);
    EXPECT_NEAR(m.divergence_mrad, livox_div, 1e-12);
    EXPECT_EQ(m.wavelength_nm, 905.0);
    const SensorDataSheet a = sheet(risley_presets(), "livox_avia");
    EXPECT_EQ(a.range_max_m, 450.0);
    EXPECT_EQ(a.wavelength_nm, 905.0);
    const SensorDataSheet v = sheet(polygon_presets(), "riegl_vux1uav");
    EXPECT_EQ(v.range_min_m, 3.0);
    EXPECT_EQ(v.range_max_m, 920.0);
    EXPECT_EQ(v.divergence_mrad, 0.5);
    EXPECT_EQ(v.wavelength_nm, 0.0);  // "near infrared"
    const SensorDataSheet q = sheet(conic_presets(), "riegl_vq880g");
    EXPECT_EQ(q.range_min_m, 10.0);
    EXPECT_EQ(q.range_max_m, 0.0);
    EXPECT_EQ(q.divergence_mrad, 0.7);
    EXPECT_EQ(q.wavelength_nm, 532.0);
    const SensorDataSheet g = sheet(conic_presets(), "riegl_vq840g");
    EXPECT_EQ(g.range_min_m, 20.0);
    EXPECT_EQ(g.range_max_m, 0.0);
    EXPECT_EQ(g.divergence_mrad, 1.0);  // the narrowest of its selectable 1-6 mrad
    EXPECT_EQ(g.wavelength_nm, 532.0);
    const SensorDataSheet l = sheet(line_presets(), "leica_als50_ii");
    EXPECT_EQ(l.range_min_m, 200.0);
    EXPECT_EQ(l.range_max_m, 6000.0);
    EXPECT_EQ(l.divergence_mrad, 0.22);
    EXPECT_EQ(l.wavelength_nm, 1064.0);
    EXPECT_EQ(mechanism_preset_names(risley_presets()), "livox_mid40 or livox_avia");
    EXPECT_EQ(mechanism_preset_names(conic_presets()), "riegl_vq880g or riegl_vq840g");
}

TEST(MechanismPresets, LivoxFieldsOfViewAreTheDataSheetCircles) {
    for (const auto& [make, fov] : {std::pair{&livox_mid40, 38.4}, std::pair{&livox_avia, 70.4}}) {
        RisleyScannerConfig c = make();
        c.duration_s = 0.5;
        const RisleyScanner s(c);
        const double m = max_off_axis_deg(test::all_pulses(s));
        // The disc of radius 2 delta: never outside, and the non-repetitive rosette comes close
        // to its rim within half a second.
        EXPECT_LE(m, fov / 2.0 + 1e-9) << fov;
        EXPECT_GT(m, fov / 2.0 - 0.05) << fov;
        EXPECT_EQ(s.pulse_count(), static_cast<std::uint64_t>(c.pulse_rate_hz / 2.0));
    }
}

TEST(MechanismPresets, Vux1SweepsThreeHundredThirtyDegreesTwoHundredLinesPerSecond) {
    PolygonScannerConfig c = riegl_vux1uav();
    c.duration_s = 0.05;
    const PolygonScanner s(c);
    const PulseBatch p = test::all_pulses(s);
    float lo = 1e9f, hi = -1e9f;
    std::uint64_t lines = 1;
    for (std::size_t i = 0; i < p.size(); ++i) {
        lo = std::min(lo, p.scan_angle_deg[i]);
        hi = std::max(hi, p.scan_angle_deg[i]);
        // A line starts where the angle jumps back (the sawtooth's fly-back).
        lines += i > 0 && p.scan_angle_deg[i] < p.scan_angle_deg[i - 1] ? 1 : 0;
        const double az = std::atan2(p.direction[i].y, p.direction[i].x) * kRadToDeg;
        ASSERT_NEAR(az, p.scan_angle_deg[i], 1e-4) << i;
    }
    EXPECT_NEAR(lo, -165.0f, 1e-4f);
    EXPECT_GT(hi, 165.0f - 330.0f / 2500.0f - 1e-3f);  // 2500 pulses per line
    EXPECT_LT(hi, 165.0f);
    EXPECT_EQ(lines, 10u);  // 200 lines/s x 0.05 s
    EXPECT_EQ(s.line_rate_hz(), 200.0);
}

TEST(MechanismPresets, Vq880gConeIsTwentyDegreesOffAxis) {
    ConicScannerConfig c = riegl_vq880g();
    c.duration_s = 0.01;
    const ConicScanner s(c);
    const PulseBatch p = test::all_pulses(s);
    for (std::size_t i = 0; i < p.size(); ++i) {
        ASSERT_NEAR(std::acos(p.direction[i].x), 20.0 / kRadToDeg, 1e-9) << i;
    }
    // 80 revolutions/s at 700 kHz: pulse 8750 (12.5 ms) is back at azimuth 0 after exactly one
    // revolution.
    EXPECT_NEAR(s.azimuth_turns(8750), 0.0, 1e-9);
    EXPECT_NEAR(s.azimuth_turns(4375), 0.5, 1e-9);
}

/// The VQ-840-G's data sheet scans +/-20 deg off nadir across the flight direction: every
/// direction of the preset's cone is 20 deg off the optical axis (1e-9 rad), so that looking down
/// from 75 m (the data sheet's UAV example) the scan reaches 75 tan 20 deg = 27.30 m to each side;
/// 100 lines/s are 100 mirror revolutions/s.
TEST(MechanismPresets, Vq840gConeIsTheDataSheetsTwentyDegreesOffNadir) {
    ConicScannerConfig c = riegl_vq840g();
    c.duration_s = 0.02;
    const ConicScanner s(c);
    const PulseBatch p = test::all_pulses(s);
    ASSERT_EQ(p.size(), 4000u);  // 200 kHz x 20 ms
    double across_m = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3d& d = p.direction[i];
        ASSERT_NEAR(std::acos(std::clamp(d.x, -1.0, 1.0)), 20.0 / kRadToDeg, 1e-9) << i;
        // Sensor x looks down 75 m onto flat ground: the ray meets it at 75 / d.x along x.
        across_m = std::max(across_m, std::abs(75.0 * d.y / d.x));
    }
    EXPECT_NEAR(across_m, 75.0 * std::tan(20.0 / kRadToDeg), 1e-6);
    EXPECT_NEAR(s.azimuth_turns(2000), 0.0, 1e-9);  // 10 ms: one revolution
    EXPECT_NEAR(s.azimuth_turns(500), 0.25, 1e-9);
}

TEST(MechanismPresets, Als50LinesAndSwath) {
    const LineScanner s(leica_als50_ii());
    EXPECT_EQ(s.config().lines_per_s(), 180.0);
    // The oscillating mirror turns at +/-37.5 deg at each line start, alternately.
    for (std::uint64_t n = 0; n < 6; ++n) {
        EXPECT_NEAR(s.scan_angle_deg_at(s.line_start_time_s(n)), n % 2 == 0 ? -37.5 : 37.5, 1e-9);
    }
    const PulseBatch p = test::all_pulses(s);
    const auto [lo, hi] = std::minmax_element(p.scan_angle_deg.begin(), p.scan_angle_deg.end());
    EXPECT_NEAR(*lo, -37.5, 1e-4);
    EXPECT_NEAR(*hi, 37.5, 0.1);  // 833.3 pulses per line: the turn falls between two
    EXPECT_EQ(p.size(), 150000u);
}

TEST(MechanismPresets, SurveyKeysOverrideThePreset) {
    const SurveySpec s = parse("{type: risley, preset: livox_mid40, pulse_rate_hz: 50000}");
    const auto* c = s.scanner.config<RisleyScanner>();
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->pulse_rate_hz, 50000.0);  // the survey's
    EXPECT_EQ(c->wedge_deg, livox_mid40().wedge_deg);
    EXPECT_EQ(s.range_min_m, 0.0);
    EXPECT_EQ(s.range_max_m, 260.0);  // the data sheet's
    EXPECT_FALSE(s.physics.has_value());

    const SurveySpec l =
        parse("{type: line, preset: leica_als50_ii, scan_rate_hz: 50, range_max_m: 1500}",
              "physics: {beam: {rings: 1}}\n");
    const auto* lc = l.scanner.config<LineScanner>();
    ASSERT_NE(lc, nullptr);
    EXPECT_EQ(lc->scan_rate_hz, 50.0);
    EXPECT_EQ(lc->scan_angle_max_deg, 37.5);
    EXPECT_EQ(l.range_min_m, 200.0);
    EXPECT_EQ(l.range_max_m, 1500.0);
    ASSERT_TRUE(l.physics.has_value());
    EXPECT_NEAR(l.physics->beam.divergence_rad, 0.22e-3, 1e-15);
    EXPECT_EQ(l.physics->radiometry.wavelength_nm, 1064.0);

    const SurveySpec o = parse("{type: conic, preset: riegl_vq880g}",
                               "physics: {wavelength_nm: 1064, beam: {divergence_mrad: 0.3}}\n");
    EXPECT_EQ(o.range_min_m, 10.0);
    EXPECT_TRUE(std::isinf(o.range_max_m));
    EXPECT_NEAR(o.physics->beam.divergence_rad, 0.3e-3, 1e-15);  // the survey's, not 0.7
    EXPECT_EQ(o.physics->radiometry.wavelength_nm, 1064.0);

    const SurveySpec b = parse("{type: conic, preset: riegl_vq840g}", "physics: {}\n");
    EXPECT_EQ(b.range_min_m, 20.0);
    EXPECT_NEAR(b.physics->beam.divergence_rad, 1.0e-3, 1e-15);  // the data sheet's
    EXPECT_EQ(b.physics->radiometry.wavelength_nm, 532.0);
    EXPECT_EQ(b.scanner.config<ConicScanner>()->rotation_rate_hz, 100.0);

    const SurveySpec v = parse("{type: polygon, preset: riegl_vux1uav}", "physics: {}\n");
    EXPECT_EQ(v.physics->radiometry.wavelength_nm, PhysicsConfig{}.radiometry.wavelength_nm);
    EXPECT_EQ(v.scanner.config<PolygonScanner>()->facets, 2);
}

TEST(MechanismPresets, UnknownPresetNamesTheChoices) {
    try {
        (void)parse("{type: risley, preset: livox_mid70}");
        FAIL() << "accepted an unknown preset";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find(
                      "s.yaml:2: scanner.preset: unknown preset (expected livox_mid40 or "
                      "livox_avia)"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW((void)parse("{type: fibre, preset: riegl_vux1uav}"), ConfigError);
}

}  // namespace
}  // namespace beamtrace
