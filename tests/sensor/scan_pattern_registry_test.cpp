// The scan pattern table: names, each survey type's own keys and documented defaults, the
// `beamtrace scan` patterns, and docs/survey.md's section per type.
#include "beamtrace/sensor/scan_pattern_registry.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/sensor/image_pattern.hpp"
#include "beamtrace/sensor/line_scanner.hpp"
#include "beamtrace/sensor/rotating_scanner.hpp"

namespace beamtrace {
namespace {

SurveySpec parse_scanner(const std::string& scanner) {
    return parse_survey_spec("scene: demo\nscanner: " + scanner + "\nplatform: {type: static}\n",
                             "s.yaml");
}

/// The message parse_scanner throws, or "" when it parses.
std::string scanner_error(const std::string& scanner) {
    try {
        (void)parse_scanner(scanner);
        return "";
    } catch (const ConfigError& e) {
        return e.what();
    }
}

TEST(ScanPatternRegistry, NamesAreUniqueAndFindTheirEntries) {
    std::set<std::string_view> names;
    for (const ScanPatternEntry& e : scan_pattern_registry()) {
        EXPECT_TRUE(names.insert(e.name).second) << e.name;
        EXPECT_EQ(find_scan_pattern(e.name), &e);
        EXPECT_FALSE(e.summary.empty()) << e.name;
        EXPECT_TRUE(e.parse != nullptr || e.static_rays != nullptr) << e.name << " is unused";
    }
    EXPECT_EQ(find_scan_pattern("spiral"), nullptr);
    EXPECT_EQ(survey_scanner_types(),
              "rotating, line, conic, polygon, risley, fibre, pinhole or scan");
    EXPECT_EQ(static_scan_pattern_choices(), "pinhole | scan | rays");
}

TEST(ScanPatternRegistry, UnknownTypesListTheTable) {
    EXPECT_NE(scanner_error("{type: spiral}")
                  .find("s.yaml:2: scanner.type: expected rotating, line, conic, polygon, risley, "
                        "fibre, pinhole or scan"),
              std::string::npos)
        << scanner_error("{type: spiral}");
    EXPECT_THROW((void)survey_scanner_type("rays"), ConfigError);  // not a survey scanner
    try {
        (void)static_scan_pattern("rotating");
        FAIL() << "rotating is not a scan pattern";
    } catch (const ConfigError& e) {
        EXPECT_STREQ(e.what(), "unknown pattern 'rotating' (expected pinhole, scan or rays)");
    }
    EXPECT_EQ(static_scan_pattern("rays").name, "rays");
    EXPECT_TRUE(static_scan_pattern("rays").reads_rays_file);
}

TEST(ScanPatternRegistry, EachSurveyTypeAcceptsExactlyItsOwnKeys) {
    std::set<std::string_view> all_keys;
    for (const ScanPatternEntry& e : scan_pattern_registry()) {
        all_keys.insert(e.keys.begin(), e.keys.end());
    }
    ASSERT_GT(all_keys.size(), 10u);
    for (const ScanPatternEntry& e : scan_pattern_registry()) {
        if (e.parse == nullptr) {
            continue;
        }
        const std::set<std::string_view> own(e.keys.begin(), e.keys.end());
        for (const std::string_view key : all_keys) {
            // Any value: a wrong one may be refused, but never as an unknown key of its own type.
            const std::string msg =
                scanner_error("{type: " + std::string(e.name) + ", " + std::string(key) + ": 1}");
            const std::string unknown = "scanner." + std::string(key) + ": unknown key for a " +
                                        std::string(e.name) + " scanner";
            EXPECT_EQ(msg.find(unknown) != std::string::npos, own.count(key) == 0)
                << e.name << " " << key << "\n"
                << msg;
        }
        EXPECT_EQ(scanner_error("{type: " + std::string(e.name) + ", range_max_m: 50}"), "")
            << e.name;
    }
}

TEST(ScanPatternRegistry, EachTypeHasItsDocumentedDefaults) {
    const SurveySpec r = parse_scanner("{type: rotating}");
    ASSERT_EQ(r.scanner.type(), "rotating");
    const auto* rc = r.scanner.config<RotatingScanner>();
    ASSERT_NE(rc, nullptr);
    EXPECT_EQ(rc->beam_elevations_deg, vlp16().beam_elevations_deg);
    EXPECT_EQ(rc->rotation_rate_hz, 10.0);
    EXPECT_EQ(rc->azimuth_resolution_deg, 0.2);
    EXPECT_FALSE(rc->spin_clockwise);
    EXPECT_EQ(rc->duration_s, 0.1);

    const SurveySpec l = parse_scanner("{type: line}");
    const auto* lc = l.scanner.config<LineScanner>();
    ASSERT_NE(lc, nullptr);
    EXPECT_EQ(lc->pulse_rate_hz, 100000.0);
    EXPECT_EQ(lc->scan_rate_hz, 100.0);
    EXPECT_EQ(lc->scan_angle_max_deg, 20.0);
    EXPECT_EQ(lc->waveform, ScanWaveform::sawtooth);
    EXPECT_EQ(lc->duration_s, 1.0);
    EXPECT_EQ(l.scanner.config<RotatingScanner>(), nullptr);

    for (const char* type : {"pinhole", "scan"}) {
        const SurveySpec s = parse_scanner(std::string("{type: ") + type + "}");
        const auto* ic = s.scanner.config<ImagePattern>();
        ASSERT_NE(ic, nullptr) << type;
        EXPECT_EQ(ic->projection,
                  std::string(type) == "scan" ? ImageProjection::scan : ImageProjection::pinhole);
        EXPECT_EQ(ic->image.width, 512);
        EXPECT_EQ(ic->image.height, 256);
        EXPECT_EQ(ic->image.hfov_rad, 1.0);
        EXPECT_EQ(ic->image.vfov_rad, 0.5);
        EXPECT_EQ(ic->frames, 1u);
        EXPECT_EQ(ic->pulse_rate_hz, 1.0e6);
        const auto grid = s.make_pattern()->image_grid();
        ASSERT_TRUE(grid.has_value());
        EXPECT_EQ(*grid, (ImageGrid{512, 256}));
    }
    EXPECT_EQ(r.range_min_m, 0.0);
    EXPECT_TRUE(std::isinf(r.range_max_m));
}

TEST(ScanPatternRegistry, ImageGridOnlyForOneFrameImages) {
    EXPECT_FALSE(parse_scanner("{type: scan, width: 4, height: 2, frames: 2}")
                     .make_pattern()
                     ->image_grid()
                     .has_value());
    EXPECT_EQ(*parse_scanner("{type: pinhole, width: 4, height: 2}").make_pattern()->image_grid(),
              (ImageGrid{4, 2}));
    EXPECT_FALSE(parse_scanner("{type: line}").make_pattern()->image_grid().has_value());
    EXPECT_FALSE(parse_scanner("{type: rotating}").make_pattern()->image_grid().has_value());
}

TEST(ScanPatternRegistry, ScannerSpecCopiesAreDeepAndMakeTheSamePattern) {
    const SurveySpec a = parse_scanner("{type: line, pulse_rate_hz: 4000, duration_s: 0.5}");
    SurveySpec b = a;  // copyable
    b.scanner = parse_scanner("{type: rotating, preset: hdl32}").scanner;
    EXPECT_EQ(a.scanner.type(), "line");
    EXPECT_EQ(a.make_pattern()->pulse_count(), 2000u);
    EXPECT_EQ(b.scanner.type(), "rotating");
    EXPECT_EQ(b.scanner.config<RotatingScanner>()->beam_elevations_deg.size(), 32u);
    const ScannerSpec fallback;
    EXPECT_EQ(fallback.type(), "rotating");
    EXPECT_EQ(fallback.make_pattern()->pulse_count(), RotatingScanner(vlp16()).pulse_count());
}

TEST(ScanPatternRegistry, StaticPatternsCastTheImageSensorsRays) {
    StaticScanInput in;
    in.sensor.width = 5;
    in.sensor.height = 3;
    for (const char* name : {"pinhole", "scan"}) {
        const ScanPatternEntry& e = static_scan_pattern(name);
        const StaticRays r = e.static_rays(in);
        const RayBatch want =
            std::string(name) == "scan" ? cast_rays_scan(in.sensor) : cast_rays_pinhole(in.sensor);
        ASSERT_EQ(r.rays.size(), 15u);
        EXPECT_EQ(r.rays.dx, want.dx);
        EXPECT_EQ(r.rays.dy, want.dy);
        EXPECT_EQ(r.rays.dz, want.dz);
        EXPECT_EQ(r.grid, (ImageGrid{5, 3}));
        EXPECT_TRUE(e.check_static(in).empty());
    }
    in.sensor.hfov_rad = 4.0;  // above pi: a scan only
    EXPECT_FALSE(static_scan_pattern("pinhole").check_static(in).empty());
    EXPECT_TRUE(static_scan_pattern("scan").check_static(in).empty());
}

TEST(ScanPatternRegistry, DocsHaveASectionWithEveryKeyOfEachType) {
    std::ifstream f(std::string(BEAMTRACE_EXAMPLES_DIR) + "/../docs/survey.md");
    ASSERT_TRUE(f) << "docs/survey.md";
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string doc = ss.str();
    for (const ScanPatternEntry& e : scan_pattern_registry()) {
        if (e.parse == nullptr) {
            continue;
        }
        const std::size_t at = doc.find("`" + std::string(e.name) + "`", doc.find("#### "));
        ASSERT_NE(at, std::string::npos) << e.name;
        const std::size_t section = doc.rfind("#### ", at);
        const std::size_t next = doc.find("#### ", at);
        const std::string text = doc.substr(section, next - section);
        for (const std::string_view key : e.keys) {
            EXPECT_NE(text.find("| `" + std::string(key) + "` |"), std::string::npos)
                << e.name << ": " << key << " is not in its docs/survey.md table";
        }
    }
}

}  // namespace
}  // namespace beamtrace
