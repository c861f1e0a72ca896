// LasReader on the real-world files in ../shared/data/las, `beamtrace info`, and LasWriter output
// checked by the independent npm validators (shared/tools/lasval) when node is available.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "independent_las.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// How a file's header bounding box relates to its points (see shared/data/las/SOURCES.md).
enum class Bounds {
    exact,        ///< every point inside the bbox within half a scale step
    unquantized,  ///< libLAS 1-point files: the point was truncated, lies up to 1 step outside
    unscaled,     ///< las/simple1_3.las stores min/max as raw integers
};

struct Expected {
    int minor;
    int format;
    std::uint64_t points;
    int record_length;
    Bounds bounds = Bounds::exact;
};

/// Version, format, count and record length from SOURCES.md (read there with a separate parser).
const std::map<std::string, Expected>& expected_files() {
    static const std::map<std::string, Expected> files = {
        {"las/autzen-thin.las", {2, 3, 10653, 34}},
        {"las/autzen.las", {2, 1, 106, 28}},
        {"las/autzen_trim.las", {2, 3, 110000, 34}},
        {"las/autzen_trim_7.las", {4, 7, 110000, 36}},
        {"las/epsg_4326.las", {2, 0, 5380, 20}},
        {"las/file_with_both_wkt_and_geotiff_vlrs.las", {4, 6, 25408, 30}},
        {"las/point-color.las", {2, 2, 1065, 26}},
        {"las/point-version-1-point-wise.las", {0, 0, 11781, 20}},
        {"las/simple.las", {2, 3, 1065, 34}},
        {"las/simple1_1.las", {1, 1, 1065, 28}},
        {"las/simple1_3.las", {3, 4, 999, 57, Bounds::unscaled}},
        {"las/simple1_4.las", {4, 7, 22600, 36}},
        {"las/test1_4.las", {4, 6, 1000, 30}},
        {"formats/1.0_0.las", {0, 0, 1, 20, Bounds::unquantized}},
        {"formats/1.0_1.las", {0, 1, 1, 28, Bounds::unquantized}},
        {"formats/1.1_0.las", {1, 0, 1, 20, Bounds::unquantized}},
        {"formats/1.1_1.las", {1, 1, 1, 28, Bounds::unquantized}},
        {"formats/1.2_0.las", {2, 0, 1, 20, Bounds::unquantized}},
        {"formats/1.2_1.las", {2, 1, 1, 28, Bounds::unquantized}},
        {"formats/1.2_2.las", {2, 2, 1, 26, Bounds::unquantized}},
        {"formats/1.2_3.las", {2, 3, 1, 34, Bounds::unquantized}},
        {"formats/1_4_w_evlr.las", {4, 6, 1000, 30}},
        {"formats/5points_14.las", {4, 6, 5, 33}},
        {"formats/extra_byte.las", {2, 1, 62, 32}},
        {"formats/extrabytes.las", {4, 3, 1065, 61}},
        {"formats/synthetic_test.las", {2, 3, 1, 34}},
        {"formats/unregistered_extra_bytes.las", {4, 6, 4, 34}},
        {"derived/append-bug.las", {4, 8, 37805, 41}},
        {"derived/las_with_several_extra_byte_bloc.las", {4, 8, 697721, 41}},
    };
    return files;
}

std::vector<fs::path> files_in(const std::string& folder) {
    std::vector<fs::path> files;
    const fs::path dir = test::shared_data("las/" + folder);
    if (fs::is_directory(dir)) {
        for (const auto& entry : fs::directory_iterator(dir)) {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// Reads every point of `path` in chunks and checks it against `e`.
void check_file(const fs::path& path, const Expected& e) {
    SCOPED_TRACE(path.string());
    LasReader reader(path);
    const LasHeader& h = reader.header();
    EXPECT_EQ(h.version_major, 1);
    EXPECT_EQ(h.version_minor, e.minor);
    EXPECT_EQ(h.point_format, e.format);
    EXPECT_EQ(h.point_count, e.points);
    EXPECT_EQ(h.point_record_length, e.record_length);
    EXPECT_EQ(h.extra_bytes_per_point(), e.record_length - las_point_record_size(e.format));
    Vec3d lo = h.min, hi = h.max;
    double tolerance = 0.5;  // scale steps
    if (e.bounds == Bounds::unscaled) {
        for (std::size_t k = 0; k < 3; ++k) {
            lo[k] = h.min[k] * h.scale[k] + h.offset[k];
            hi[k] = h.max[k] * h.scale[k] + h.offset[k];
        }
    } else if (e.bounds == Bounds::unquantized) {
        tolerance = 1.0;
    }
    std::vector<LasPoint> chunk(4096);
    std::uint64_t count = 0;
    std::uint64_t outside = 0;
    LasPoint first, last;
    while (const std::size_t n = reader.read(chunk)) {
        if (count == 0) {
            first = chunk[0];
        }
        for (std::size_t i = 0; i < n; ++i) {
            const LasPoint& p = chunk[i];
            const double xyz[3] = {p.x, p.y, p.z};
            for (std::size_t k = 0; k < 3; ++k) {
                const double slack = tolerance * h.scale[k] * (1 + 1e-9);
                outside +=
                    std::isfinite(xyz[k]) && xyz[k] >= lo[k] - slack && xyz[k] <= hi[k] + slack ? 0
                                                                                                : 1;
            }
            EXPECT_EQ(p.extra_bytes.size(), h.extra_bytes_per_point());
        }
        last = chunk[n - 1];
        count += n;
    }
    EXPECT_EQ(count, h.point_count);
    EXPECT_EQ(outside, 0u) << "coordinates outside the header bounds";
    if (count > 0) {
        EXPECT_TRUE(std::isfinite(first.gps_time) && std::isfinite(last.gps_time));
        if (!las_format_has_gps_time(e.format)) {
            EXPECT_EQ(first.gps_time, 0.0);
            EXPECT_EQ(last.gps_time, 0.0);
        }
        EXPECT_LE(std::fabs(first.scan_angle_deg), 180.0f);
        EXPECT_LE(std::fabs(last.scan_angle_deg), 180.0f);
    }
}

TEST(LasReaderFiles, EveryValidSampleReadsCompletely) {
    BEAMTRACE_REQUIRE_FILE(test::shared_data("las/las"));
    std::size_t checked = 0;
    for (const std::string folder : {"las", "formats", "derived"}) {
        for (const auto& path : files_in(folder)) {
            const std::string rel = folder + "/" + path.filename().string();
            const auto it = expected_files().find(rel);
            if (it == expected_files().end()) {
                ADD_FAILURE() << rel << " is new: add its expectations to expected_files()";
                continue;
            }
            check_file(path, it->second);
            ++checked;
        }
    }
    EXPECT_EQ(checked, expected_files().size());
}

// Values below were printed by the independent copc.js reader:
// `node lasval/read.mjs FILE 3` (shared/tools/lasval, see shared/data/VALIDATORS.md).

TEST(LasReaderFiles, Format3FirstPointMatchesCopcJs) {
    const fs::path path = test::shared_data("las/formats/1.2_3.las");
    BEAMTRACE_REQUIRE_FILE(path);
    LasReader reader(path);
    EXPECT_EQ(reader.header().system_identifier, "libLAS");
    EXPECT_EQ(reader.header().generating_software, "libLAS 1.2");
    EXPECT_EQ(reader.header().creation_year, 2008);
    EXPECT_EQ(reader.header().creation_day_of_year, 78);
    ASSERT_EQ(reader.vlrs().size(), 2u);
    EXPECT_EQ(reader.vlrs()[0].user_id, "LASF_Projection");
    EXPECT_EQ(reader.vlrs()[0].record_id, 34735);
    EXPECT_EQ(reader.vlrs()[0].data.size(), 64u);
    EXPECT_EQ(reader.vlrs()[1].record_id, 34737);
    EXPECT_EQ(reader.vlrs()[1].data.size(), 39u);
    std::array<LasPoint, 1> p;
    ASSERT_EQ(reader.read(p), 1u);
    EXPECT_DOUBLE_EQ(p[0].x, 470692.44);
    EXPECT_DOUBLE_EQ(p[0].y, 4602888.9);
    EXPECT_DOUBLE_EQ(p[0].z, 16.0);
    EXPECT_EQ(p[0].intensity, 0);
    EXPECT_EQ(p[0].return_number, 2);
    EXPECT_EQ(p[0].number_of_returns, 0);  // as stored: the file is odd
    EXPECT_EQ(p[0].classification, 2);
    EXPECT_EQ(p[0].scan_angle_deg, -13.0f);
    EXPECT_DOUBLE_EQ(p[0].gps_time, 1205902800.0);
    EXPECT_EQ(p[0].red, 255);
    EXPECT_EQ(p[0].green, 12);
    EXPECT_EQ(p[0].blue, 234);
}

TEST(LasReaderFiles, Format6PointsMatchCopcJs) {
    const fs::path path = test::shared_data("las/formats/5points_14.las");
    BEAMTRACE_REQUIRE_FILE(path);
    LasReader reader(path);
    const LasHeader& h = reader.header();
    EXPECT_EQ(h.global_encoding, 17);
    EXPECT_EQ(h.offset, Vec3d(600000, 4800000, 0));
    EXPECT_EQ(h.points_by_return,
              (std::array<std::uint64_t, 15>{1, 2, 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, 0}));
    ASSERT_EQ(reader.vlrs().size(), 3u);
    EXPECT_EQ(reader.vlrs()[2].user_id, "funny");
    EXPECT_EQ(reader.vlrs()[2].record_id, 12345);
    EXPECT_EQ(reader.vlrs()[2].description, "just a funny VLR");
    std::array<LasPoint, 2> p;
    ASSERT_EQ(reader.read(p), 2u);
    EXPECT_DOUBLE_EQ(p[0].x, 630499.95);
    EXPECT_DOUBLE_EQ(p[0].y, 4834749.17);
    EXPECT_DOUBLE_EQ(p[0].z, 62.15);
    EXPECT_EQ(p[0].intensity, 60);
    EXPECT_EQ(p[0].return_number, 2);
    EXPECT_EQ(p[0].number_of_returns, 2);
    EXPECT_TRUE(p[0].overlap);
    EXPECT_FALSE(p[0].synthetic || p[0].key_point || p[0].withheld);
    EXPECT_EQ(p[0].scanner_channel, 1);
    EXPECT_EQ(p[0].classification, 2);
    EXPECT_FLOAT_EQ(p[0].scan_angle_deg, 21.0f);
    EXPECT_DOUBLE_EQ(p[0].gps_time, 53413162.5604);
    EXPECT_EQ(p[0].extra_bytes.size(), 3u);
    EXPECT_EQ(p[1].return_number, 8);
    EXPECT_EQ(p[1].number_of_returns, 9);
    EXPECT_EQ(p[1].classification, 41);
    EXPECT_FLOAT_EQ(p[1].scan_angle_deg, 21.402f);
}

TEST(LasReaderFiles, Format8AndEvlrMatchCopcJs) {
    const fs::path path = test::shared_data("las/derived/append-bug.las");
    BEAMTRACE_REQUIRE_FILE(path);
    LasReader reader(path);
    std::array<LasPoint, 1> p;
    ASSERT_EQ(reader.read(p), 1u);
    EXPECT_DOUBLE_EQ(p[0].x, 698011.6);
    EXPECT_DOUBLE_EQ(p[0].y, 6259973.14);
    EXPECT_DOUBLE_EQ(p[0].z, 96.43);
    EXPECT_EQ(p[0].intensity, 120);
    EXPECT_TRUE(p[0].scan_direction);
    EXPECT_EQ(p[0].point_source_id, 802);
    EXPECT_FLOAT_EQ(p[0].scan_angle_deg, 12.0f);
    EXPECT_DOUBLE_EQ(p[0].gps_time, 307644287.96229345);
    EXPECT_EQ(p[0].red, 32768);
    EXPECT_EQ(p[0].green, 35328);
    EXPECT_EQ(p[0].blue, 37376);
    EXPECT_EQ(p[0].nir, 32000);

    const fs::path evlr_path = test::shared_data("las/formats/1_4_w_evlr.las");
    LasReader evlr(evlr_path);
    ASSERT_EQ(evlr.vlrs().size(), 3u);
    const LasVlr& v = evlr.vlrs()[2];
    EXPECT_TRUE(v.extended);
    EXPECT_EQ(v.user_id, "pylastest");
    EXPECT_EQ(v.record_id, 42);
    EXPECT_EQ(v.description, "just a test evlr");
    EXPECT_EQ(v.data.size(), 16u);
    ASSERT_EQ(evlr.read(p), 1u);
    EXPECT_DOUBLE_EQ(p[0].x, 1694510.3869346841);
    EXPECT_DOUBLE_EQ(p[0].z, 5598.3596128149675);
    EXPECT_FLOAT_EQ(p[0].scan_angle_deg, 18.03f);
    EXPECT_EQ(p[0].point_source_id, 202);
    EXPECT_DOUBLE_EQ(p[0].gps_time, 83177420.53400505);
}

TEST(LasReaderFiles, Format4WavePacketsAndOtherVersions) {
    const fs::path path = test::shared_data("las/las/simple1_3.las");
    BEAMTRACE_REQUIRE_FILE(path);
    LasReader reader(path);
    EXPECT_EQ(reader.header().global_encoding & kLasGlobalEncodingInternalWaveform,
              kLasGlobalEncodingInternalWaveform);
    EXPECT_GT(reader.header().start_of_waveform_data, 0u);
    std::array<LasPoint, 1> p;
    ASSERT_EQ(reader.read(p), 1u);
    // loaders.gl (copc.js does not read format 4).
    EXPECT_DOUBLE_EQ(p[0].x, -234935.84100000001);
    EXPECT_DOUBLE_EQ(p[0].y, 5800843.145);
    EXPECT_DOUBLE_EQ(p[0].z, 265.094);
    EXPECT_EQ(p[0].intensity, 1);
    EXPECT_EQ(p[0].classification, 1);
    EXPECT_GT(p[0].wave_packet_size, 0u);

    // LAS 1.1 format 1 and the synthetic flag of a legacy format.
    LasReader v11(test::shared_data("las/las/simple1_1.las"));
    ASSERT_EQ(v11.read(p), 1u);
    EXPECT_DOUBLE_EQ(p[0].x, 637012.24);
    EXPECT_EQ(p[0].intensity, 143);
    EXPECT_TRUE(p[0].scan_direction);
    EXPECT_EQ(p[0].scan_angle_deg, -9.0f);
    EXPECT_EQ(p[0].user_data, 132);
    EXPECT_EQ(p[0].point_source_id, 7326);
    EXPECT_DOUBLE_EQ(p[0].gps_time, 245380.78254962614);
    // Format 2 (RGB, no GPS time).
    LasReader rgb(test::shared_data("las/las/point-color.las"));
    ASSERT_EQ(rgb.read(p), 1u);
    EXPECT_DOUBLE_EQ(p[0].x, 494428.61);
    EXPECT_DOUBLE_EQ(p[0].y, 4877455.58);
    EXPECT_DOUBLE_EQ(p[0].z, 131.57);
    EXPECT_EQ(p[0].intensity, 143);
    EXPECT_EQ(p[0].point_source_id, 7326);
    EXPECT_EQ(p[0].gps_time, 0.0);
    EXPECT_EQ(p[0].red, 68);
    EXPECT_EQ(p[0].green, 77);
    EXPECT_EQ(p[0].blue, 88);
    const auto synthetic = read_las_points(test::shared_data("las/formats/synthetic_test.las"));
    ASSERT_EQ(synthetic.size(), 1u);
    EXPECT_TRUE(synthetic[0].synthetic);
    EXPECT_EQ(synthetic[0].classification, 0);
    EXPECT_EQ(synthetic[0].x, 1.0);
}

TEST(LasReaderFiles, EdgeFilesReadOrFailWithTheFileName) {
    BEAMTRACE_REQUIRE_FILE(test::shared_data("las/edge"));
    // What each valid-but-odd file really holds; every other file must be rejected with the
    // message fragment given.
    const std::map<std::string, std::uint64_t> readable = {
        {"1.2-empty-geotiff-vlrs.las", 43}, {"bad-geotiff-keys.las", 10}, {"lots_of_vlr.las", 1},
        {"no-points-1.3.las", 0},           {"no-points.las", 0},         {"utm15.las", 1},
    };
    const std::map<std::string, std::string> rejected = {
        {"1.2-no-points-truncated.las", "header says 1065 points but the file holds only 0"},
        {"1.2-with-color-clipped.las", "header says 1065 points but the file holds only 1064"},
        {"bad_vlr_count.las", "VLR 3 of 3"},
    };
    std::size_t seen = 0;
    for (const auto& path : files_in("edge")) {
        const std::string name = path.filename().string();
        SCOPED_TRACE(name);
        ++seen;
        if (path.extension() == ".laz") {
            continue;  // tests/laz/laz_reader_test.cpp reads or refuses each
        }
        if (const auto it = rejected.find(name); it != rejected.end()) {
            test::expect_input_error(read_las_points, path, it->second);
        } else if (const auto ok = readable.find(name); ok != readable.end()) {
            LasReader reader(path);
            EXPECT_EQ(reader.header().point_count, ok->second);
            EXPECT_EQ(read_las_points(path).size(), ok->second);
            if (name == "lots_of_vlr.las") {
                EXPECT_EQ(reader.vlrs().size(), 390u);
            }
        } else {
            ADD_FAILURE() << name << " is new: say whether it should read or fail";
        }
    }
    EXPECT_EQ(seen, 17u);
}

// --- `beamtrace info` ---------------------------------------------------------------------

using test::run_command;

TEST(LasInfoCli, PrintsTheHeaderSummary) {
    const fs::path path = test::shared_data("las/formats/1_4_w_evlr.las");
    BEAMTRACE_REQUIRE_FILE(path);
    const auto r =
        run_command(std::string(BEAMTRACE_CLI_PATH) + " info '" + path.string() + "' --points 2");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    for (const char* fragment :
         {"LAS version:         1.4", "point format:        6", "point count:         1000",
          "pylastest", "just a test evlr", "EVLRs:               1", "#1: xyz"}) {
        EXPECT_NE(r.out.find(fragment), std::string::npos) << fragment << "\n" << r.out;
    }
}

TEST(LasInfoCli, BrokenFileExitsTwoWithOneLine) {
    const fs::path path = test::shared_data("las/edge/1.2-with-color-clipped.las");
    BEAMTRACE_REQUIRE_FILE(path);
    const auto r = run_command(std::string(BEAMTRACE_CLI_PATH) + " info '" + path.string() + "'");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_NE(r.out.find(path.string()), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("1064"), std::string::npos) << r.out;
}

// --- independent validation of LasWriter output --------------------------------------------

/// 5000 points whose every field varies (flags, channel, returns, angles, colours).
std::vector<LasPoint> varied_points() {
    std::vector<LasPoint> points(5000);
    for (std::size_t i = 0; i < points.size(); ++i) {
        LasPoint& p = points[i];
        p.x = 634000.0 + static_cast<double>(i) * 0.37 + 0.0004;
        p.y = 4851000.0 - static_cast<double>(i % 977) * 1.91;
        p.z = 50.0 + static_cast<double>(i % 13) - 0.0049;
        p.number_of_returns = static_cast<std::uint8_t>(1 + i % 15);
        p.return_number = static_cast<std::uint8_t>(1 + i % p.number_of_returns);
        p.classification = static_cast<std::uint8_t>(i % 256);
        p.scan_angle_deg = static_cast<float>(static_cast<double>(i % 361) * 0.5 - 90.0);
        p.gps_time = 3.1e8 + static_cast<double>(i) * 1.37e-5;
        p.intensity = static_cast<std::uint16_t>(i * 13);
        p.user_data = static_cast<std::uint8_t>(i * 7);
        p.point_source_id = static_cast<std::uint16_t>(i * 11);
        p.synthetic = i % 2 == 1;
        p.key_point = i % 3 == 1;
        p.withheld = i % 5 == 1;
        p.overlap = i % 7 == 1;
        p.scanner_channel = static_cast<std::uint8_t>(i % 4);
        p.scan_direction = i % 11 == 1;
        p.edge_of_flight_line = i % 13 == 1;
        p.red = static_cast<std::uint16_t>(i * 7);
        p.green = static_cast<std::uint16_t>(65535 - i * 5);
        p.blue = static_cast<std::uint16_t>(i * 3);
        p.nir = static_cast<std::uint16_t>(i * 17);
    }
    return points;
}

TEST(LasWriterValidator, IndependentReadersDecodeEveryFieldWeWrote) {
    BEAMTRACE_REQUIRE_LASVAL(lasval);
    test::TempDir dir;
    const std::vector<LasPoint> points = varied_points();
    for (const int format : {6, 7, 8}) {
        LasWriterConfig config =
            las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200}, 0.01);
        config.point_format = format;
        config.vlrs.push_back({"beamtrace", 1, "scene", {'h', 'i'}, false, 0});
        const fs::path path = dir / ("format" + std::to_string(format) + ".las");
        LasWriter writer(path, config);
        writer.write(points);
        writer.close();
        // shared/tools/lasval's own consistency checks.
        const auto r = run_command("node '" + (lasval / "read.mjs").string() + "' '" +
                                   path.string() + "' 5 --json");
        EXPECT_EQ(r.exit_code, 0) << "format " << format << ":\n" << r.out;
        EXPECT_EQ(r.out.find("FAIL"), std::string::npos) << r.out;
        // Every field of every point, and the header.
        const auto decoded = test::decode_independently(lasval, path, dir.path());
        ASSERT_TRUE(decoded) << format;
        const std::string what = "format " + std::to_string(format);
        test::expect_decodes_as(*decoded, points, {format, config.scale, config.offset}, what);
        const auto& vlrs = decoded->facts.at("vlrs");
        ASSERT_EQ(vlrs.size(), 1u) << what;
        EXPECT_EQ(vlrs[0].at("userId"), "beamtrace") << what;
        EXPECT_EQ(vlrs[0].at("recordId"), 1) << what;
        EXPECT_EQ(vlrs[0].at("description"), "scene") << what;
        EXPECT_EQ(vlrs[0].at("data"), "6869") << what;  // "hi"
    }
}

}  // namespace
}  // namespace beamtrace
