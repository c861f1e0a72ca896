// Rotating polygon mirror: the scan-angle range 2 (360 / facets) u, the line rate facets x f,
// the facet channel, chunking, the survey file's keys and defaults, and the refused settings.
#include "beamtrace/sensor/polygon_scanner.hpp"

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

constexpr double kDegToRad = std::numbers::pi / 180.0;

double beam_angle_deg(const Vec3d& d) {
    return std::atan2(d.y, d.x) / kDegToRad;
}

PolygonScannerConfig config() {
    PolygonScannerConfig c;
    c.pulse_rate_hz = 120'000.0;
    c.facets = 3;
    c.rotation_rate_hz = 20.0;  // 60 lines/s: 2000 pulses per line
    c.usable_fraction = 0.6;    // A = 120 x 0.6 = 72 deg
    c.duration_s = 0.5;         // 30 lines
    return c;
}

TEST(PolygonScanner, ScanAngleRangeIsTwiceTheFacetAngleTimesTheUsableFraction) {
    const PolygonScanner scanner(config());
    ASSERT_EQ(scanner.pulse_count(), 60'000u);
    EXPECT_DOUBLE_EQ(scanner.scan_angle_max_deg(), 72.0);
    const PulseBatch p = test::all_pulses(scanner);
    double lo = 1e9, hi = -1e9;
    const double step = 2.0 * 72.0 / 2000.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double s = beam_angle_deg(p.direction[i]);
        // The closed form: a linear ramp over [-A, A) every 1 / (facets f) seconds.
        ASSERT_NEAR(s, -72.0 + step * static_cast<double>(i % 2000), 1e-9) << i;
        ASSERT_NEAR(p.scan_angle_deg[i], s, 1e-5);
        ASSERT_EQ(p.direction[i].z, 0.0);
        ASSERT_EQ(p.time_s[i], static_cast<double>(i) / 120'000.0);
        lo = std::min(lo, s);
        hi = std::max(hi, s);
    }
    // 2 (360 / facets) u, the last pulse of a line being one step short of +A.
    EXPECT_NEAR(hi - lo + step, 2.0 * (360.0 / 3.0) * 0.6, 1e-9);
    EXPECT_NEAR(lo, -72.0, 1e-12);
}

TEST(PolygonScanner, LineRateIsFacetsTimesRotationRateAndChannelIsTheFacet) {
    const PolygonScanner scanner(config());
    EXPECT_DOUBLE_EQ(scanner.line_rate_hz(), 60.0);
    const PulseBatch p = test::all_pulses(scanner);
    std::size_t line_starts = 1;  // pulse 0 starts line 0
    for (std::size_t i = 1; i < p.size(); ++i) {
        const bool fly_back = p.scan_angle_deg[i] < p.scan_angle_deg[i - 1];
        line_starts += fly_back ? 1 : 0;
        if (fly_back) {
            ASSERT_NEAR(p.time_s[i] * 60.0, std::round(p.time_s[i] * 60.0), 1e-9) << i;
        }
        ASSERT_EQ(scanner.line_of_pulse(i), i / 2000);
        ASSERT_EQ(p.channel[i], (i / 2000) % 3) << i;
    }
    EXPECT_EQ(static_cast<double>(line_starts) / 0.5, 60.0);  // lines per second
}

TEST(PolygonScanner, ChunkingDoesNotMatter) {
    PolygonScannerConfig c = config();
    c.pulse_rate_hz = 77'777.0;  // not a multiple of the line rate
    const PolygonScanner scanner(c);
    test::expect_chunking_does_not_matter(scanner, {1, 13, 4096});
}

TEST(PolygonScanner, ValidationListsEveryProblem) {
    PolygonScannerConfig c;
    c.pulse_rate_hz = 0.0;
    c.facets = 1;
    c.rotation_rate_hz = -2.0;
    c.usable_fraction = 1.5;
    c.duration_s = INFINITY;
    EXPECT_EQ(c.validate().size(), 5u);
    try {
        PolygonScanner scanner(c);
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("polygon scanner: ", 0), 0u) << msg;
        for (const char* key :
             {"pulse_rate_hz", "facets", "rotation_rate_hz", "usable_fraction", "duration_s"}) {
            EXPECT_NE(msg.find(key), std::string::npos) << msg;
        }
    }
    PolygonScannerConfig two;
    two.facets = 2;
    two.usable_fraction = 1.0;  // +-180 deg: the whole circle
    EXPECT_EQ(two.validate().size(), 1u);
    PolygonScannerConfig fast;
    fast.rotation_rate_hz = 40'000.0;  // 160 000 lines/s at 300 000 pulses/s
    ASSERT_EQ(fast.validate().size(), 1u);
    EXPECT_NE(fast.validate()[0].find("two pulses per line"), std::string::npos);
}

SurveySpec parse(const std::string& scanner) {
    return parse_survey_spec("scene: demo\nscanner: " + scanner + "\nplatform: {type: static}\n",
                             "s.yaml");
}

TEST(PolygonScanner, SurveyFileKeysAndDefaults) {
    const SurveySpec d = parse("{type: polygon}");
    const auto* dc = d.scanner.config<PolygonScanner>();
    ASSERT_NE(dc, nullptr);
    EXPECT_EQ(dc->pulse_rate_hz, 300'000.0);
    EXPECT_EQ(dc->facets, 4);
    EXPECT_EQ(dc->rotation_rate_hz, 25.0);
    EXPECT_EQ(dc->usable_fraction, 0.5);
    EXPECT_EQ(dc->duration_s, 1.0);
    const SurveySpec s = parse(
        "{type: polygon, pulse_rate_hz: 5000, facets: 6, rotation_rate_hz: 10, "
        "usable_fraction: 0.9, duration_s: 0.2}");
    const auto* sc = s.scanner.config<PolygonScanner>();
    ASSERT_NE(sc, nullptr);
    EXPECT_EQ(sc->facets, 6);
    EXPECT_EQ(sc->usable_fraction, 0.9);
    EXPECT_EQ(s.make_pattern()->pulse_count(), 1000u);
    for (const char* bad : {"{type: polygon, facets: 2.5}", "{type: polygon, facets: 1}"}) {
        try {
            (void)parse(bad);
            FAIL() << bad;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("s.yaml:2: scanner.facets: expected an integer"),
                      std::string::npos)
                << e.what();
        }
    }
    try {
        (void)parse("{type: polygon, usable_fraction: 1.2}");
        FAIL() << "usable_fraction 1.2";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("scanner: usable_fraction must be in (0, 1]"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace beamtrace
