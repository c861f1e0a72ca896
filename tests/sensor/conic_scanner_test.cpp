// Conic (Palmer) scanner: every direction at the off-axis angle, the azimuth 2 pi f t, chunking,
// the survey file's keys and defaults, and the refused settings.
#include "beamtrace/sensor/conic_scanner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "sensor/scan_pattern_test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegToRad = kPi / 180.0;

/// `x` wrapped into [-pi, pi).
double wrap_pi(double x) {
    return x - 2.0 * kPi * std::floor((x + kPi) / (2.0 * kPi));
}

ConicScannerConfig config() {
    ConicScannerConfig c;
    c.pulse_rate_hz = 40'000.0;
    c.rotation_rate_hz = 37.0;  // not a divisor of the pulse rate
    c.off_axis_deg = 15.0;
    c.duration_s = 0.25;
    c.start_time_s = 1000.5;
    return c;
}

TEST(ConicScanner, EveryDirectionIsAtTheOffAxisAngleAndTheAzimuthIsTwoPiFT) {
    const ConicScanner scanner(config());
    ASSERT_EQ(scanner.pulse_count(), 10'000u);
    const PulseBatch p = test::all_pulses(scanner);
    double lo = 1e9, hi = -1e9;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3d d = p.direction[i];
        const double t = static_cast<double>(i) / 40'000.0;  // since pulse 0
        ASSERT_EQ(p.time_s[i], 1000.5 + t);
        ASSERT_NEAR(length(d), 1.0, 1e-15);
        const double off_axis = std::atan2(std::hypot(d.y, d.z), d.x);
        ASSERT_NEAR(off_axis, 15.0 * kDegToRad, 1e-9) << i;
        const double azimuth = std::atan2(d.z, d.y);  // about +x, from +y towards +z
        ASSERT_NEAR(wrap_pi(azimuth - 2.0 * kPi * 37.0 * t), 0.0, 1e-9) << i;
        ASSERT_NEAR(p.scan_angle_deg[i] * kDegToRad, azimuth, 1e-6) << i;
        ASSERT_EQ(p.channel[i], 0);
        lo = std::min(lo, static_cast<double>(p.scan_angle_deg[i]));
        hi = std::max(hi, static_cast<double>(p.scan_angle_deg[i]));
    }
    EXPECT_LT(lo, -179.0);  // the azimuth covers the whole circle, in [-180, 180)
    EXPECT_GT(hi, 179.0);
    EXPECT_EQ(p.direction[0], (Vec3d{std::cos(15.0 * kDegToRad), std::sin(15.0 * kDegToRad), 0.0}));
}

TEST(ConicScanner, OneRevolutionPerOverRotationRate) {
    ConicScannerConfig c = config();
    c.rotation_rate_hz = 50.0;  // 800 pulses per revolution
    const ConicScanner scanner(c);
    const PulseBatch p = test::all_pulses(scanner);
    for (std::size_t i = 0; i + 800 < p.size(); ++i) {
        ASSERT_NEAR(p.direction[i + 800].y, p.direction[i].y, 1e-12);
        ASSERT_NEAR(p.direction[i + 800].z, p.direction[i].z, 1e-12);
    }
    EXPECT_NEAR(p.direction[200].y, 0.0, 1e-15);  // a quarter turn: towards +z
    EXPECT_GT(p.direction[200].z, 0.0);
}

TEST(ConicScanner, ChunkingDoesNotMatter) {
    const ConicScanner scanner(config());
    test::expect_chunking_does_not_matter(scanner, {1, 7, 4096});
}

TEST(ConicScanner, ValidationListsEveryProblem) {
    ConicScannerConfig c;
    c.pulse_rate_hz = -1.0;
    c.rotation_rate_hz = 0.0;
    c.off_axis_deg = 90.0;
    c.duration_s = 0.0;
    c.start_time_s = NAN;
    EXPECT_EQ(c.validate().size(), 5u);
    try {
        ConicScanner scanner(c);
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("conic scanner: ", 0), 0u) << msg;
        for (const char* key :
             {"pulse_rate_hz", "rotation_rate_hz", "off_axis_deg", "duration_s", "start_time_s"}) {
            EXPECT_NE(msg.find(key), std::string::npos) << msg;
        }
    }
    ConicScannerConfig fast;
    fast.rotation_rate_hz = 50'000.0;  // two pulses per revolution
    ASSERT_EQ(fast.validate().size(), 1u);
    EXPECT_NE(fast.validate()[0].find("three pulses per revolution"), std::string::npos);
}

SurveySpec parse(const std::string& scanner) {
    return parse_survey_spec("scene: demo\nscanner: " + scanner + "\nplatform: {type: static}\n",
                             "s.yaml");
}

TEST(ConicScanner, SurveyFileKeysAndDefaults) {
    const SurveySpec d = parse("{type: conic}");
    const auto* dc = d.scanner.config<ConicScanner>();
    ASSERT_NE(dc, nullptr);
    EXPECT_EQ(dc->pulse_rate_hz, 100'000.0);
    EXPECT_EQ(dc->rotation_rate_hz, 50.0);
    EXPECT_EQ(dc->off_axis_deg, 20.0);
    EXPECT_EQ(dc->duration_s, 1.0);
    const SurveySpec s = parse(
        "{type: conic, pulse_rate_hz: 2000, rotation_rate_hz: 10, off_axis_deg: 7.5, "
        "duration_s: 0.5}");
    const auto* sc = s.scanner.config<ConicScanner>();
    ASSERT_NE(sc, nullptr);
    EXPECT_EQ(sc->off_axis_deg, 7.5);
    EXPECT_EQ(s.make_pattern()->pulse_count(), 1000u);
    try {
        (void)parse("{type: conic, off_axis_deg: 95}");
        FAIL() << "95 deg off axis";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("s.yaml:2: scanner: off_axis_deg must be in (0, 90)"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace beamtrace
