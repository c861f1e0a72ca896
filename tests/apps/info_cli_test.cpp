// `beamtrace info`: the CRS line (WKT record or GeoTIFF keys, with warnings for broken keys),
// `--stats` and `--stats --json`, on real files; no file makes it crash.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>

#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

test::RunResult info(const fs::path& file, const std::string& flags = "") {
    return test::run_command(std::string(BEAMTRACE_CLI_PATH) + " info '" + file.string() + "' " +
                             flags);
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(InfoCli, PrintsTheCrsOfGeoTiffKeysAndWkt) {
    struct Case {
        const char* file;
        std::vector<const char*> expected;
    };
    const std::vector<Case> cases = {
        {"las/edge/utm15.las",
         {"CRS:                 EPSG:26915, from the GeoTIFF keys",
          "citation: \"UTM Zone 15, Northern Hemisphere\""}},
        {"las/edge/bad-geotiff-keys.las",
         {"CRS:                 EPSG:32617 (WGS 84 / UTM zone 17N), from the GeoTIFF keys",
          "warning: GeoTIFF keys: 4 of 8 key entries have KeyID 0 (blank)"}},
        {"las/edge/1.2-empty-geotiff-vlrs.las",
         {"CRS:                 none readable from the GeoTIFF keys",
          "warning: GeoTIFF keys: neither ProjectedCSTypeGeoKey"}},
        {"las/las/epsg_4326.las", {"CRS:                 EPSG:4326 (WGS 84), from the GeoTIFF"}},
        {"las/las/file_with_both_wkt_and_geotiff_vlrs.las",
         {"CRS:                 PROJCS (NAD83_2011_Nebraska_ft), from the OGC WKT record",
          "warning: both a WKT record and GeoTIFF keys"}},
        {"las/las/simple.las", {"CRS:                 none\n"}},
    };
    for (const Case& c : cases) {
        const fs::path path = test::shared_data(c.file);
        BEAMTRACE_REQUIRE_FILE(path);
        const auto r = info(path);
        ASSERT_EQ(r.exit_code, 0) << c.file << "\n" << r.out;
        for (const char* e : c.expected) {
            EXPECT_TRUE(has(r.out, e)) << c.file << ": " << e << "\n" << r.out;
        }
    }
}

TEST(InfoCli, CoordinatesWithTheDecimalsOfTheScale) {
    // autzen_trim's header holds 848935.2000000001 (a double near 848935.20) and scale 0.01.
    const fs::path path = test::shared_data("las/laz/autzen_trim.laz");
    BEAMTRACE_REQUIRE_FILE(path);
    const auto r = info(path, "--points 1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(has(r.out, "min:                 636001.76 848935.20 406.26\n")) << r.out;
    EXPECT_TRUE(has(r.out, "max:                 637179.22 849497.90 520.51\n")) << r.out;
    EXPECT_TRUE(has(r.out, "#0: xyz 637177.98 849393.95 411.19,")) << r.out;
}

TEST(InfoCli, NegativeZeroReadsZero) {
    // autzen.las stores its offsets as -0.0.
    const fs::path path = test::shared_data("las/las/autzen.las");
    BEAMTRACE_REQUIRE_FILE(path);
    const auto r = info(path);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(has(r.out, "offset:              0 0 0\n")) << r.out;
    EXPECT_FALSE(has(r.out, "-0 ")) << r.out;
}

TEST(InfoCli, StatsAsTextAndJson) {
    const fs::path path = test::shared_data("las/las/simple.las");
    BEAMTRACE_REQUIRE_FILE(path);
    const auto text = info(path, "--stats");
    ASSERT_EQ(text.exit_code, 0) << text.out;
    for (const char* e : {"statistics:          1065 points read", "  x:                 min ",
                          "  gps time:          min ", "  classification:    1: ",
                          "  return number:     1: ", "  density:           "}) {
        EXPECT_TRUE(has(text.out, e)) << e << "\n" << text.out;
    }
    const auto r = info(path, "--stats --json");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto json = nlohmann::json::parse(r.out);  // one object, nothing else on stdout
    EXPECT_EQ(json.at("point_format"), 3);
    EXPECT_EQ(json.at("stats").at("points"), 1065);
    std::uint64_t total = 0;
    for (const auto& [cls, count] : json.at("stats").at("by_classification").items()) {
        total += count.get<std::uint64_t>();
    }
    EXPECT_EQ(total, 1065u);
    const double area = json.at("stats").at("footprint_area").get<double>();
    EXPECT_GT(area, 0);
    EXPECT_NEAR(json.at("stats").at("density_per_area").get<double>(), 1065 / area, 1e-9);
    const auto plain = nlohmann::json::parse(info(path, "--json").out);
    EXPECT_FALSE(plain.contains("stats"));
    EXPECT_EQ(plain.at("crs").at("source"), "none");
}

TEST(InfoCli, EveryRealFileGivesStatsOrOneLineError) {
    std::size_t seen = 0;
    for (const char* folder : {"las/edge", "las/las", "las/formats"}) {
        const fs::path dir = test::shared_data(folder);
        BEAMTRACE_REQUIRE_FILE(dir);
        for (const auto& entry : fs::directory_iterator(dir)) {
            if (entry.path().extension() != ".las") {
                continue;
            }
            ++seen;
            const auto r = info(entry.path(), "--stats --json");
            if (r.exit_code == 0) {
                const auto json = nlohmann::json::parse(r.out);
                EXPECT_EQ(json.at("stats").at("points"), json.at("point_count")) << entry.path();
            } else {
                EXPECT_EQ(r.exit_code, 2) << entry.path() << "\n" << r.out;
                EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
            }
        }
    }
    EXPECT_GT(seen, 30u);
}

}  // namespace
}  // namespace beamtrace
