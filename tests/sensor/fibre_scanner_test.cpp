// Fibre-array line scanner: the fibre spacing fan / (n - 1), the firing order, chunking, the
// survey file's keys and defaults, and the refused settings.
#include "beamtrace/sensor/fibre_scanner.hpp"

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

FibreScannerConfig config() {
    FibreScannerConfig c;
    c.pulse_rate_hz = 12'000.0;
    c.fibres = 9;
    c.fan_deg = 16.0;  // 2 deg apart
    c.duration_s = 0.1;
    c.start_time_s = 2.0;
    return c;
}

TEST(FibreScanner, FibresAreFanOverNMinusOneApartAndFireInSequence) {
    const FibreScanner scanner(config());
    ASSERT_EQ(scanner.pulse_count(), 1200u);
    const PulseBatch p = test::all_pulses(scanner);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t k = i % 9;
        ASSERT_EQ(p.channel[i], k) << "fibre i mod n fires pulse i";
        ASSERT_EQ(p.time_s[i], 2.0 + static_cast<double>(i) / 12'000.0);
        ASSERT_NEAR(beam_angle_deg(p.direction[i]), -8.0 + 2.0 * static_cast<double>(k), 1e-12)
            << i;
        ASSERT_NEAR(p.scan_angle_deg[i], -8.0 + 2.0 * static_cast<double>(k), 1e-6);
        ASSERT_EQ(p.direction[i].z, 0.0);
        ASSERT_NEAR(length(p.direction[i]), 1.0, 1e-15);
        if (k > 0) {  // neighbours in the firing order are neighbours in the fan
            ASSERT_NEAR(beam_angle_deg(p.direction[i]) - beam_angle_deg(p.direction[i - 1]),
                        16.0 / 8.0, 1e-12);
        }
    }
    EXPECT_NEAR(beam_angle_deg(p.direction[0]), -8.0, 1e-12);
    EXPECT_NEAR(beam_angle_deg(p.direction[8]), 8.0, 1e-12);  // the fan's full width
}

TEST(FibreScanner, ChunkingDoesNotMatter) {
    FibreScannerConfig c = config();
    c.fibres = 127;
    const FibreScanner scanner(c);
    test::expect_chunking_does_not_matter(scanner, {1, 13, 4096});
}

TEST(FibreScanner, ValidationListsEveryProblem) {
    FibreScannerConfig c;
    c.pulse_rate_hz = 0.0;
    c.fibres = 1;
    c.fan_deg = 180.0;
    c.duration_s = 0.0;
    c.start_time_s = -INFINITY;
    EXPECT_EQ(c.validate().size(), 5u);
    try {
        FibreScanner scanner(c);
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.rfind("fibre scanner: ", 0), 0u) << msg;
        for (const char* key :
             {"pulse_rate_hz", "fibres", "fan_deg", "duration_s", "start_time_s"}) {
            EXPECT_NE(msg.find(key), std::string::npos) << msg;
        }
    }
    FibreScannerConfig many;
    many.fibres = 65537;  // beyond the 16-bit channel
    EXPECT_EQ(many.validate().size(), 1u);
}

SurveySpec parse(const std::string& scanner) {
    return parse_survey_spec("scene: demo\nscanner: " + scanner + "\nplatform: {type: static}\n",
                             "s.yaml");
}

TEST(FibreScanner, SurveyFileKeysAndDefaults) {
    const SurveySpec d = parse("{type: fibre}");
    const auto* dc = d.scanner.config<FibreScanner>();
    ASSERT_NE(dc, nullptr);
    EXPECT_EQ(dc->pulse_rate_hz, 83'000.0);
    EXPECT_EQ(dc->fibres, 127);
    EXPECT_EQ(dc->fan_deg, 14.0);
    EXPECT_EQ(dc->duration_s, 1.0);
    const SurveySpec s =
        parse("{type: fibre, pulse_rate_hz: 1000, fibres: 4, fan_deg: 6, duration_s: 0.5}");
    const auto* sc = s.scanner.config<FibreScanner>();
    ASSERT_NE(sc, nullptr);
    EXPECT_EQ(sc->fibres, 4);
    EXPECT_EQ(s.make_pattern()->pulse_count(), 500u);
    try {
        (void)parse("{type: fibre, fan_deg: 200}");
        FAIL() << "a 200 deg fan";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("s.yaml:2: scanner: fan_deg must be in (0, 180)"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace beamtrace
