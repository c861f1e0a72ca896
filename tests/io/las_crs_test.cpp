// CRS: WKT built from EPSG codes, `crs:` parsing, GeoTIFF keys (rasters and LAS files), the OGC
// WKT VLR of LAS outputs checked by parsing the file's bytes here (not by the writer's code).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "beamtrace/core/crs.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_crs.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/scene/raster_terrain.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "io/independent_las.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(Crs, UtmZonesFromTheCodeAlone) {
    const auto north = crs_wkt_for_epsg(32632);
    ASSERT_TRUE(north);
    EXPECT_EQ(north->rfind("PROJCS[\"WGS 84 / UTM zone 32N\",GEOGCS[\"WGS 84\"", 0), 0u) << *north;
    EXPECT_TRUE(has(*north, "PARAMETER[\"central_meridian\",9]"));
    EXPECT_TRUE(has(*north, "PARAMETER[\"false_northing\",0]"));
    EXPECT_TRUE(has(*north, "PARAMETER[\"false_easting\",500000]"));
    EXPECT_TRUE(has(*north, "PARAMETER[\"scale_factor\",0.9996]"));
    EXPECT_TRUE(has(*north, "SPHEROID[\"WGS 84\",6378137,298.257223563"));
    EXPECT_TRUE(north->ends_with("AUTHORITY[\"EPSG\",\"32632\"]]")) << *north;
    const auto south = crs_wkt_for_epsg(32701);
    ASSERT_TRUE(south);
    EXPECT_TRUE(has(*south, "UTM zone 1S"));
    EXPECT_TRUE(has(*south, "PARAMETER[\"central_meridian\",-177]"));
    EXPECT_TRUE(has(*south, "PARAMETER[\"false_northing\",10000000]"));
    const auto z60 = crs_wkt_for_epsg(32660);
    ASSERT_TRUE(z60);
    EXPECT_TRUE(has(*z60, "PARAMETER[\"central_meridian\",177]"));
    const auto etrs = crs_wkt_for_epsg(25832);
    ASSERT_TRUE(etrs);
    EXPECT_TRUE(has(*etrs, "ETRS89 / UTM zone 32N"));
    EXPECT_TRUE(has(*etrs, "SPHEROID[\"GRS 1980\",6378137,298.257222101"));
    EXPECT_TRUE(has(*crs_wkt_for_epsg(4326), "AUTHORITY[\"EPSG\",\"4326\"]]"));
    for (const std::uint32_t unknown : {0u, 32600u, 32661u, 32700u, 32761u, 2056u, 25827u}) {
        EXPECT_FALSE(crs_wkt_for_epsg(unknown)) << unknown;
    }
    const Crs minimal = crs_from_epsg(2056, true);
    EXPECT_EQ(minimal.wkt, "PROJCS[\"EPSG:2056\",AUTHORITY[\"EPSG\",\"2056\"]]");
    EXPECT_EQ(crs_from_epsg(4269, false).wkt, "GEOGCS[\"EPSG:4269\",AUTHORITY[\"EPSG\",\"4269\"]]");
}

TEST(Crs, SummaryReadsTheTopLevelAuthority) {
    const WktSummary s = summarize_wkt(*crs_wkt_for_epsg(32632));
    EXPECT_EQ(s.keyword, "PROJCS");
    EXPECT_EQ(s.name, "WGS 84 / UTM zone 32N");
    EXPECT_EQ(s.epsg, 32632u);  // not the GEOGCS's 4326 nor the unit's 9001
    const WktSummary esri = summarize_wkt(test::read_file(test::shared_mesh("terrain/dem_hd.prj")));
    EXPECT_EQ(esri.keyword, "PROJCS");
    EXPECT_EQ(esri.name, "WGS_1984_UTM_Zone_32N");
    EXPECT_EQ(esri.epsg, 0u);
    const WktSummary wkt2 =
        summarize_wkt("PROJCRS[\"x\",BASEGEOGCRS[\"y\",ID[\"EPSG\",4326]],ID[\"EPSG\",32631]]");
    EXPECT_EQ(wkt2.epsg, 32631u);
    EXPECT_EQ(summarize_wkt("garbage[[\"").epsg, 0u);  // never throws
    EXPECT_EQ(describe_crs(crs_from_epsg(32632, true)), "EPSG:32632 (WGS 84 / UTM zone 32N)");
    EXPECT_EQ(describe_crs({}), "none");
}

TEST(Crs, SettingTextIsAnEpsgCodeOrWkt) {
    std::string problem;
    const auto epsg = parse_crs_text("  epsg:32632 ", problem);
    ASSERT_TRUE(epsg) << problem;
    EXPECT_EQ(epsg->epsg, 32632u);
    EXPECT_EQ(epsg->wkt, *crs_wkt_for_epsg(32632));
    const std::string wkt =
        "GEOGCS[\"mine\",DATUM[\"d\",SPHEROID[\"s\",1,2]],AUTHORITY[\"EPSG\","
        "\"4326\"]]";
    const auto given = parse_crs_text(wkt, problem);
    ASSERT_TRUE(given) << problem;
    EXPECT_EQ(given->wkt, wkt);  // kept as written
    EXPECT_EQ(given->epsg, 4326u);
    for (const char* bad :
         {"EPSG:2056", "EPSG:32x", "EPSG:", "UTM 32", "PROJCS[\"a\"", "PROJCS[\"a]\"", "[]", ""}) {
        problem.clear();
        EXPECT_FALSE(parse_crs_text(bad, problem)) << bad;
        EXPECT_FALSE(problem.empty()) << bad;
    }
    EXPECT_FALSE(parse_crs_text("GEOGCS[\"" + std::string(kMaxWktBytes, 'x') + "\"]", problem));
    EXPECT_TRUE(has(problem, "LAS VLR")) << problem;
    ASSERT_FALSE(parse_crs_text("EPSG:2056", problem));
    EXPECT_TRUE(has(problem, "OGC WKT")) << problem;
}

TEST(Crs, GeoTiffRastersGiveTheirEpsgCode) {
    const fs::path sub = test::shared_mesh("terrain/dem_hd_sub.tif");
    const fs::path full = test::shared_mesh("terrain/dem_hd.tif");
    BEAMTRACE_REQUIRE_FILE(sub);
    BEAMTRACE_REQUIRE_FILE(full);
    EXPECT_EQ(load_geotiff(sub).crs.epsg, 25832u);  // ProjectedCSTypeGeoKey = 25832
    const Raster r = load_geotiff(full);            // 3072 = 32632 besides 2048 = 4326
    EXPECT_EQ(r.crs, crs_from_epsg(32632, true));
    EXPECT_TRUE(load_esri_ascii_grid(test::shared_mesh("terrain/dem_hd.asc")).crs.empty());
}

TEST(Crs, SceneFileSettingWinsOverTheRasters) {
    const fs::path sub = test::shared_mesh("terrain/dem_hd_sub.tif");
    BEAMTRACE_REQUIRE_FILE(sub);
    test::TempDir dir;
    const std::string parts = "parts:\n  - raster: '" + sub.string() + "'\n";
    const SceneSpec plain =
        parse_scene_spec("origin_m: [478000, 5474000, 0]\n" + parts, dir / "scene.yaml");
    EXPECT_TRUE(plain.crs.empty());
    EXPECT_EQ(build_scene(plain).crs.epsg, 25832u);
    const SceneSpec given = parse_scene_spec(
        "crs: EPSG:32632\norigin_m: [478000, 5474000, 0]\n" + parts, dir / "scene.yaml");
    EXPECT_EQ(given.crs.epsg, 32632u);
    EXPECT_EQ(build_scene(given).crs, crs_from_epsg(32632, true));
    // Two rasters naming different CRSs, without crs:, are refused.
    const fs::path full = test::shared_mesh("terrain/dem_hd.tif");
    BEAMTRACE_REQUIRE_FILE(full);
    const SceneSpec mixed = parse_scene_spec(
        "origin_m: [478000, 5474000, 0]\n" + parts + "  - raster: '" + full.string() + "'\n",
        dir / "scene.yaml");
    try {
        (void)build_scene(mixed);
        ADD_FAILURE() << "rasters with different CRSs were accepted";
    } catch (const InputError& e) {
        EXPECT_TRUE(has(e.what(), "EPSG:32632") && has(e.what(), "EPSG:25832")) << e.what();
    }
}

TEST(Crs, BadSceneSettingIsAConfigErrorNamingTheKey) {
    test::TempDir dir;
    try {
        (void)parse_scene_spec("crs: EPSG:99999\nparts:\n  - sphere: {radius_m: 1}\n",
                               dir / "scene.yaml");
        ADD_FAILURE() << "accepted";
    } catch (const ConfigError& e) {
        EXPECT_TRUE(has(e.what(), "scene.yaml:1") && has(e.what(), "crs")) << e.what();
    }
}

// --- the LAS records -------------------------------------------------------------------------

std::uint16_t u16(const std::string& b, std::size_t at) {
    std::uint16_t v = 0;
    std::memcpy(&v, b.data() + at, 2);
    return v;
}
std::uint32_t u32(const std::string& b, std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}

struct RawVlr {
    std::string user_id;
    std::uint16_t record_id = 0;
    std::string payload;
};

/// The VLRs of a LAS file straight from its bytes (LAS 1.4 R15 table 4: 54-byte headers).
std::vector<RawVlr> raw_vlrs(const std::string& bytes) {
    std::vector<RawVlr> out;
    std::size_t at = u16(bytes, 94);  // header size
    const std::uint32_t n = u32(bytes, 100);
    for (std::uint32_t i = 0; i < n; ++i) {
        RawVlr v;
        v.user_id = std::string(bytes.data() + at + 2, 16).c_str();
        v.record_id = u16(bytes, at + 18);
        const std::uint16_t length = u16(bytes, at + 20);
        v.payload = bytes.substr(at + 54, length);
        out.push_back(v);
        at += 54 + length;
    }
    return out;
}

TEST(LasCrs, WktVlrIsNulTerminatedUnderLasfProjection) {
    const std::string wkt = *crs_wkt_for_epsg(32632);
    test::TempDir dir;
    LasWriterConfig config;
    config.vlrs.push_back(las_wkt_vlr(wkt));
    LasWriter writer(dir / "crs.las", config);
    writer.write(std::vector<LasPoint>(3));
    writer.close();
    const std::string bytes = test::read_file(dir / "crs.las");
    EXPECT_NE(u16(bytes, 6) & (1u << 4), 0u);  // global encoding: WKT
    const auto vlrs = raw_vlrs(bytes);
    ASSERT_EQ(vlrs.size(), 1u);
    EXPECT_EQ(vlrs[0].user_id, "LASF_Projection");
    EXPECT_EQ(vlrs[0].record_id, 2112);
    EXPECT_EQ(vlrs[0].payload, wkt + std::string(1, '\0'));
    LasReader reader(dir / "crs.las");
    const LasFileCrs read = las_file_crs(reader.header(), reader.vlrs());
    EXPECT_EQ(read.source, LasCrsSource::wkt);
    EXPECT_EQ(read.crs.wkt, wkt);
    EXPECT_EQ(read.crs.epsg, 32632u);
    EXPECT_TRUE(read.warnings.empty());
    EXPECT_THROW((void)las_wkt_vlr(std::string(70000, 'x')), ConfigError);
    EXPECT_THROW((void)las_wkt_vlr(std::string("A\0B", 3)), ConfigError);
}

TEST(LasCrs, GeoTiffKeysOfRealFiles) {
    const fs::path utm15 = test::shared_data("las/edge/utm15.las");
    const fs::path bad = test::shared_data("las/edge/bad-geotiff-keys.las");
    const fs::path empty = test::shared_data("las/edge/1.2-empty-geotiff-vlrs.las");
    BEAMTRACE_REQUIRE_FILE(utm15);
    BEAMTRACE_REQUIRE_FILE(bad);
    BEAMTRACE_REQUIRE_FILE(empty);
    const auto crs_of = [](const fs::path& p) {
        LasReader r(p);
        return las_file_crs(r.header(), r.vlrs());
    };
    const LasFileCrs a = crs_of(utm15);
    EXPECT_EQ(a.source, LasCrsSource::geotiff);
    EXPECT_EQ(a.crs.epsg, 26915u);  // NAD83 / UTM zone 15N: named, not built
    EXPECT_TRUE(a.projected);
    EXPECT_EQ(a.citation, "UTM Zone 15, Northern Hemisphere");
    EXPECT_TRUE(a.warnings.empty()) << a.warnings.front();
    const LasFileCrs b = crs_of(bad);  // 8 keys claimed, 4 of them blank
    EXPECT_EQ(b.crs.epsg, 32617u);
    ASSERT_EQ(b.warnings.size(), 1u);
    EXPECT_TRUE(has(b.warnings[0], "KeyID 0")) << b.warnings[0];
    const LasFileCrs c = crs_of(empty);
    EXPECT_EQ(c.source, LasCrsSource::geotiff);
    EXPECT_TRUE(c.crs.empty());
    ASSERT_EQ(c.warnings.size(), 1u);
    EXPECT_TRUE(has(c.warnings[0], "ProjectedCSTypeGeoKey")) << c.warnings[0];
}

TEST(LasCrs, MalformedGeoKeyDirectoriesWarn) {
    LasHeader h;
    h.point_format = 1;
    LasVlr dir;
    dir.user_id = kLasProjectionUserId;
    dir.record_id = kLasGeoKeyDirectoryRecordId;
    for (const std::size_t size : {0u, 3u, 7u}) {
        dir.data.assign(size, 0);
        const LasFileCrs c = las_file_crs(h, std::span<const LasVlr>(&dir, 1));
        EXPECT_TRUE(c.crs.empty());
        EXPECT_FALSE(c.warnings.empty()) << size;
    }
    // A directory claiming 100 keys with room for one: the one is read.
    const std::uint16_t keys[] = {1, 1, 0, 100, 3072, 0, 1, 32633};
    dir.data.assign(reinterpret_cast<const std::uint8_t*>(keys),
                    reinterpret_cast<const std::uint8_t*>(keys) + sizeof keys);
    const LasFileCrs c = las_file_crs(h, std::span<const LasVlr>(&dir, 1));
    EXPECT_EQ(c.crs.epsg, 32633u);
    ASSERT_FALSE(c.warnings.empty());
    EXPECT_TRUE(has(c.warnings[0], "claims 100 keys")) << c.warnings[0];
    // Random directories and citation records (the ASan build checks every access): never a
    // throw, and a code only from a 3072/2048 key.
    LasVlr ascii;
    ascii.user_id = kLasProjectionUserId;
    ascii.record_id = 34737;
    std::uint32_t state = 12345;
    const auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return static_cast<std::uint16_t>(state >> 16);
    };
    for (int round = 0; round < 3000; ++round) {
        std::vector<std::uint16_t> shorts(next() % 40);
        for (auto& v : shorts) {
            const std::uint16_t r = next();
            v = r % 4 == 0 ? std::uint16_t{3072} : (r % 4 == 1 ? std::uint16_t{34737} : next());
        }
        if (shorts.size() > 3) {
            shorts[3] = next() % 12;
        }
        dir.data.assign(reinterpret_cast<const std::uint8_t*>(shorts.data()),
                        reinterpret_cast<const std::uint8_t*>(shorts.data() + shorts.size()));
        if (next() % 2 == 0 && !dir.data.empty()) {
            dir.data.pop_back();
        }
        ascii.data.assign(next() % 64, static_cast<std::uint8_t>('a' + round % 26));
        const LasVlr both[] = {dir, ascii};
        EXPECT_NO_THROW((void)las_file_crs(h, both));
    }
}

// --- surveys -------------------------------------------------------------------------------

TEST(LasCrs, SrtmGeoTiffSurveyWritesEpsg32632AsWkt) {
    BEAMTRACE_REQUIRE_FILE(test::shared_mesh("terrain/dem_hd.tif"));
    test::TempDir dir;
    const std::string scene = std::string(BEAMTRACE_EXAMPLES_DIR) + "/scenes/srtm_terrain.yaml";
    test::run_survey_in("scene: '" + scene +
                            "'\nscanner: {type: line, pulse_rate_hz: 2000, scan_rate_hz: 50, "
                            "scan_angle_max_deg: 20, duration_s: 0.05}\n"
                            "platform: {type: legs, speed_mps: 60, waypoints_m: "
                            "[[-10, 0, 1500], [10, 0, 1500]]}\n"
                            "mount: {boresight_deg: [0, -90, 0]}\n",
                        dir, 2, 1 << 16, 1);
    const std::string bytes = test::read_file(dir / "out" / "points.las");
    EXPECT_NE(u16(bytes, 6) & (1u << 4), 0u);
    const auto vlrs = raw_vlrs(bytes);
    ASSERT_FALSE(vlrs.empty());
    EXPECT_EQ(vlrs[0].user_id, "LASF_Projection");
    EXPECT_EQ(vlrs[0].record_id, 2112);
    EXPECT_EQ(vlrs[0].payload, *crs_wkt_for_epsg(32632) + std::string(1, '\0'));
    const auto r = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " info '" +
                                     (dir / "out" / "points.las").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(has(r.out,
                    "CRS:                 EPSG:32632 (WGS 84 / UTM zone 32N), from the "
                    "OGC WKT record"))
        << r.out;
}

TEST(LasCrs, IndependentReaderSeesTheWktRecord) {
    BEAMTRACE_REQUIRE_LASVAL(lasval);
    BEAMTRACE_REQUIRE_FILE(test::shared_mesh("terrain/dem_hd.tif"));
    test::TempDir dir;
    const std::string scene = std::string(BEAMTRACE_EXAMPLES_DIR) + "/scenes/srtm_terrain.yaml";
    test::run_survey_in("scene: '" + scene +
                            "'\nscanner: {type: line, pulse_rate_hz: 2000, scan_rate_hz: 50, "
                            "scan_angle_max_deg: 20, duration_s: 0.02}\n"
                            "platform: {type: legs, speed_mps: 60, waypoints_m: "
                            "[[-10, 0, 1500], [10, 0, 1500]]}\n"
                            "mount: {boresight_deg: [0, -90, 0]}\n",
                        dir, 1, 1 << 16, 1);
    const auto decoded = test::decode_independently(lasval, dir / "out" / "points.las", dir.path());
    ASSERT_TRUE(decoded);
    EXPECT_NE(decoded->facts.at("globalEncoding").get<int>() & 16, 0);
    const auto& vlr = decoded->facts.at("vlrs").at(0);
    EXPECT_EQ(vlr.at("userId"), "LASF_Projection");
    EXPECT_EQ(vlr.at("recordId"), 2112);
    std::string hex;
    for (const char ch : *crs_wkt_for_epsg(32632) + std::string(1, '\0')) {
        char two[3];
        std::snprintf(two, sizeof two, "%02x", static_cast<unsigned char>(ch));
        hex += two;
    }
    EXPECT_EQ(vlr.at("data"), hex);
}

TEST(LasCrs, SceneFileCrsReachesTheSurveyLas) {
    test::TempDir dir;
    const std::string wkt = "PROJCS[\"my grid\",AUTHORITY[\"EPSG\",\"2056\"]]";
    test::write_file(dir / "plane.yaml",
                     "crs: '" + wkt +
                         "'\nparts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], "
                         "size_m: 50}\n");
    test::run_survey_in(
        "scene: plane.yaml\n"
        "scanner: {type: line, pulse_rate_hz: 1000, scan_rate_hz: 50, "
        "scan_angle_max_deg: 20, duration_s: 0.02}\n"
        "platform: {type: legs, speed_mps: 10, waypoints_m: [[0, 0, 50], "
        "[1, 0, 50]]}\nmount: {boresight_deg: [0, -90, 0]}\n",
        dir, 1, 1 << 16, 1);
    const auto vlrs = raw_vlrs(test::read_file(dir / "out" / "points.las"));
    ASSERT_FALSE(vlrs.empty());
    EXPECT_EQ(vlrs[0].record_id, 2112);
    EXPECT_EQ(vlrs[0].payload, wkt + std::string(1, '\0'));
}

TEST(LasCrs, SurveyWithoutACrsWritesNoProjectionRecord) {
    test::TempDir dir;
    test::write_file(dir / "plane.yaml",
                     "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 50}\n");
    test::run_survey_in(
        "scene: plane.yaml\n"
        "scanner: {type: line, pulse_rate_hz: 1000, scan_rate_hz: 50, "
        "scan_angle_max_deg: 20, duration_s: 0.02}\n"
        "platform: {type: legs, speed_mps: 10, waypoints_m: [[0, 0, 50], "
        "[1, 0, 50]]}\nmount: {boresight_deg: [0, -90, 0]}\n",
        dir, 1, 1 << 16, 1);
    for (const RawVlr& v : raw_vlrs(test::read_file(dir / "out" / "points.las"))) {
        EXPECT_NE(v.user_id, "LASF_Projection");
    }
}

}  // namespace
}  // namespace beamtrace
