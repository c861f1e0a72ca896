// Risley prism pair: the directions equal the first-order two-prism formula, the rosette's
// period for a rational rotation ratio, chunking, the survey file's keys and defaults, and the
// refused settings.
#include "beamtrace/sensor/risley_scanner.hpp"

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

RisleyScannerConfig config(double f1, double f2) {
    RisleyScannerConfig c;
    c.pulse_rate_hz = 10'000.0;
    c.wedge_deg = 20.0;
    c.refractive_index = 1.5;  // delta = 10 deg per prism
    c.rotation_rate_1_hz = f1;
    c.rotation_rate_2_hz = f2;
    c.duration_s = 0.3;
    c.start_time_s = 5.0;
    return c;
}

TEST(RisleyScanner, DirectionsEqualTheFirstOrderTwoPrismFormula) {
    const RisleyScanner scanner(config(121.6, -77.7));
    ASSERT_EQ(scanner.pulse_count(), 3000u);
    const PulseBatch p = test::all_pulses(scanner);
    const double delta = 0.5 * 20.0 * kDegToRad;  // (n - 1) alpha
    double rho_max = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double t = static_cast<double>(i) / 10'000.0;
        ASSERT_EQ(p.time_s[i], 5.0 + t);
        const double t1 = 2.0 * kPi * 121.6 * t, t2 = 2.0 * kPi * -77.7 * t;
        const double dy = delta * (std::cos(t1) + std::cos(t2));
        const double dz = delta * (std::sin(t1) + std::sin(t2));
        const Vec3d d = p.direction[i];
        ASSERT_NEAR(length(d), 1.0, 1e-15);
        // The deviation applied as a rotation: |D| from the x axis, in D's azimuth about x.
        const double rho = std::atan2(std::hypot(d.y, d.z), d.x);
        ASSERT_NEAR(rho, std::hypot(dy, dz), 1e-9) << i;
        if (std::hypot(dy, dz) > 1e-6) {
            const double psi = std::atan2(d.z, d.y), want = std::atan2(dz, dy);
            ASSERT_NEAR(std::remainder(psi - want, 2.0 * kPi), 0.0, 1e-9) << i;
        }
        // To first order the direction is [1, D_y, D_z] (tan rho - rho < 0.016 at 20 deg).
        ASSERT_NEAR(d.y / d.x, dy, 0.1 * delta) << i;
        ASSERT_NEAR(d.z / d.x, dz, 0.1 * delta) << i;
        ASSERT_NEAR(p.scan_angle_deg[i], std::atan2(d.y, d.x) / kDegToRad, 1e-4);
        ASSERT_EQ(p.channel[i], 0);
        rho_max = std::max(rho_max, rho);
    }
    EXPECT_LE(rho_max, 2.0 * delta + 1e-12);  // a disc of radius 2 delta
    EXPECT_GT(rho_max, 1.99 * delta);
    EXPECT_NEAR(p.direction[0].x, std::cos(2.0 * delta), 1e-15);  // both prisms towards +y
    EXPECT_NEAR(p.direction[0].y, std::sin(2.0 * delta), 1e-15);
}

TEST(RisleyScanner, RosetteRepeatsAfterItsPeriod) {
    // 30 Hz and -20 Hz: gcd 10 Hz, the rosette repeats every 0.1 s = 1000 pulses.
    const RisleyScanner scanner(config(30.0, -20.0));
    const PulseBatch p = test::all_pulses(scanner);
    double half_period_diff = 0.0;
    for (std::size_t i = 0; i + 1000 < p.size(); ++i) {
        ASSERT_NEAR(length(p.direction[i + 1000] - p.direction[i]), 0.0, 1e-12) << i;
        if (i + 500 < p.size()) {
            half_period_diff =
                std::max(half_period_diff, length(p.direction[i + 500] - p.direction[i]));
        }
    }
    EXPECT_GT(half_period_diff, 0.1);  // and not after half of it
    // Counter-rotating at equal rates, theta_1 = -theta_2 makes D_z = 0: a line in the x-y plane.
    const RisleyScanner line(config(25.0, -25.0));
    const PulseBatch q = test::all_pulses(line);
    for (std::size_t i = 0; i < q.size(); ++i) {
        ASSERT_NEAR(q.direction[i].z, 0.0, 1e-12) << i;
    }
}

TEST(RisleyScanner, ChunkingDoesNotMatter) {
    const RisleyScanner scanner(config(121.6, -77.7));
    test::expect_chunking_does_not_matter(scanner, {1, 13, 4096});
}

TEST(RisleyScanner, ValidationListsEveryProblem) {
    RisleyScannerConfig c;
    c.pulse_rate_hz = NAN;
    c.wedge_deg = 50.0;
    c.refractive_index = 1.0;
    c.rotation_rate_1_hz = INFINITY;
    c.duration_s = -1.0;
    EXPECT_EQ(c.validate().size(), 5u);
    try {
        RisleyScanner scanner(c);
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("risley scanner: ", 0), 0u) << msg;
        for (const char* key : {"pulse_rate_hz", "wedge_deg", "refractive_index",
                                "rotation_rate_1_hz", "duration_s"}) {
            EXPECT_NE(msg.find(key), std::string::npos) << msg;
        }
    }
    RisleyScannerConfig wide;
    wide.wedge_deg = 40.0;
    wide.refractive_index = 2.5;  // 60 deg per prism: beyond 90 deg off axis
    EXPECT_EQ(wide.validate().size(), 1u);
    RisleyScannerConfig still;
    still.rotation_rate_1_hz = still.rotation_rate_2_hz = 0.0;
    EXPECT_EQ(still.validate().size(), 1u);
}

SurveySpec parse(const std::string& scanner) {
    return parse_survey_spec("scene: demo\nscanner: " + scanner + "\nplatform: {type: static}\n",
                             "s.yaml");
}

TEST(RisleyScanner, SurveyFileKeysAndDefaults) {
    const SurveySpec d = parse("{type: risley}");
    const auto* dc = d.scanner.config<RisleyScanner>();
    ASSERT_NE(dc, nullptr);
    EXPECT_EQ(dc->pulse_rate_hz, 100'000.0);
    EXPECT_EQ(dc->wedge_deg, 18.8);
    EXPECT_EQ(dc->refractive_index, 1.509);
    EXPECT_EQ(dc->rotation_rate_1_hz, 121.6);
    EXPECT_EQ(dc->rotation_rate_2_hz, -77.7);
    EXPECT_EQ(dc->duration_s, 1.0);
    const SurveySpec s = parse(
        "{type: risley, pulse_rate_hz: 1000, wedge_deg: 10, refractive_index: 1.8, "
        "rotation_rate_1_hz: 5, rotation_rate_2_hz: -3.5, duration_s: 2}");
    const auto* sc = s.scanner.config<RisleyScanner>();
    ASSERT_NE(sc, nullptr);
    EXPECT_EQ(sc->rotation_rate_2_hz, -3.5);
    EXPECT_NEAR(sc->prism_deviation_rad(), 8.0 * kDegToRad, 1e-15);
    EXPECT_EQ(s.make_pattern()->pulse_count(), 2000u);
    try {
        (void)parse("{type: risley, refractive_index: 0.9}");
        FAIL() << "n = 0.9";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("s.yaml:2: scanner: refractive_index must be in"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace beamtrace
