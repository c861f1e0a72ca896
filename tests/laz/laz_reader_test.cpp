// LAZ through LasReader: every LAZ sample reads like its uncompressed twin (or, where there is
// none, like the decode of two independent readers, laz-perf and laz-rs), or is refused with
// an InputError naming the file; parallel and sequential decodes agree; seek works in chunks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "../io/independent_las.hpp"
#include "../test_support.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

std::vector<LasPoint> read_all(const fs::path& path, unsigned threads) {
    LasReader reader(path, threads);
    std::vector<LasPoint> points(static_cast<std::size_t>(reader.header().point_count));
    EXPECT_EQ(reader.read(points), points.size());
    return points;
}

/// The twin's header and points must be the LAZ file's.
void expect_same_as(const fs::path& laz, const fs::path& las) {
    SCOPED_TRACE(laz.filename().string());
    LasReader a(laz);
    LasReader b(las);
    EXPECT_EQ(a.header().point_format, b.header().point_format);
    EXPECT_EQ(a.header().point_record_length, b.header().point_record_length);
    ASSERT_EQ(a.header().point_count, b.header().point_count);
    EXPECT_EQ(a.header().scale, b.header().scale);
    EXPECT_EQ(a.header().offset, b.header().offset);
    const std::vector<LasPoint> pa = read_all(laz, 2);
    const std::vector<LasPoint> pb = read_all(las, 1);
    ASSERT_EQ(pa.size(), pb.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < pa.size(); ++i) {
        if (!(pa[i] == pb[i]) && differ++ < 3) {
            ADD_FAILURE() << "point " << i << " differs: x " << pa[i].x << " / " << pb[i].x
                          << ", gps " << pa[i].gps_time << " / " << pb[i].gps_time;
        }
    }
    EXPECT_EQ(differ, 0u);
}

TEST(LazReader, LayeredFilesReadLikeTheirLasTwins) {
    BEAMTRACE_REQUIRE_FILE(test::shared_data("las/laz"));
    expect_same_as(test::shared_data("las/laz/1_4_w_evlr.laz"),
                   test::shared_data("las/formats/1_4_w_evlr.las"));
    expect_same_as(test::shared_data("las/laz/append-bug.laz"),
                   test::shared_data("las/derived/append-bug.las"));
    expect_same_as(test::shared_data("las/laz/las_with_several_extra_byte_bloc.laz"),
                   test::shared_data("las/derived/las_with_several_extra_byte_bloc.las"));
}

TEST(LazReader, PointwiseFilesReadLikeTheirLasTwins) {
    BEAMTRACE_REQUIRE_FILE(test::shared_data("las/laz"));
    expect_same_as(test::shared_data("las/laz/autzen_trim.laz"),
                   test::shared_data("las/las/autzen_trim.las"));
    expect_same_as(test::shared_data("las/laz/simple.laz"),
                   test::shared_data("las/las/simple.las"));
    expect_same_as(test::shared_data("las/laz/extra.laz"),
                   test::shared_data("las/formats/extrabytes.las"));
    expect_same_as(test::shared_data("las/edge/point-version-1-point-wise.laz"),
                   test::shared_data("las/las/point-version-1-point-wise.las"));
    expect_same_as(test::shared_data("las/edge/simple-laszip-compressor-version-1.2r0.laz"),
                   test::shared_data("las/las/simple.las"));
}

TEST(LazReader, EveryLazSampleReadsOrFailsWithTheFileName) {
    BEAMTRACE_REQUIRE_FILE(test::shared_data("las/edge"));
    const std::map<std::string, std::string> refused = {
        {"broken_coder.laz", "unknown coder"}, {"broken_compressor.laz", "compressor"},
        {"broken_size.laz", "LASzip VLR"},     {"broken_type.laz", "LASzip VLR"},
        {"broken_version.laz", "LASzip VLR"},
    };
    std::size_t seen = 0;
    for (const char* folder : {"las/laz", "las/edge"}) {
        for (const auto& entry : fs::directory_iterator(test::shared_data(folder))) {
            if (entry.path().extension() != ".laz") {
                continue;
            }
            const std::string name = entry.path().filename().string();
            SCOPED_TRACE(name);
            ++seen;
            if (const auto it = refused.find(name); it != refused.end()) {
                test::expect_input_error(read_las_points, entry.path(), it->second);
                continue;
            }
            LasReader reader(entry.path());
            EXPECT_EQ(read_las_points(entry.path()).size(), reader.header().point_count);
        }
    }
    EXPECT_EQ(seen, 28u);
}

TEST(LazReader, LayeredWavePacketsAreConsistentPulseByPulse) {
    // No independent reader decodes wave packet LAZ; the packets themselves tell: each point's
    // packet is its predecessor's (a later return of the pulse) or the one right after it (a new
    // pulse), one new packet per first return.
    const fs::path path = test::shared_data("las/laz/fullwave.laz");
    BEAMTRACE_REQUIRE_FILE(path);
    const std::vector<LasPoint> points = read_all(path, 2);
    ASSERT_EQ(points.size(), 10750u);
    EXPECT_EQ(points[0].wave_data_offset, 60u);
    std::size_t same = 0, next = 0;
    for (std::size_t i = 1; i < points.size(); ++i) {
        const LasPoint& p = points[i];
        const LasPoint& q = points[i - 1];
        const bool fields = p.wave_descriptor_index == 1 && p.wave_packet_size == 4968 &&
                            std::isfinite(p.wave_return_location);
        same += fields && p.wave_data_offset == q.wave_data_offset ? 1 : 0;
        next += fields && p.wave_data_offset == q.wave_data_offset + q.wave_packet_size ? 1 : 0;
    }
    EXPECT_EQ(same + next, points.size() - 1);
    EXPECT_EQ(next + 1, LasReader(path).header().points_by_return[0]);
}

TEST(LazReader, NoPointsReadsAsEmpty) {
    const fs::path path = test::shared_data("las/edge/no-points-1.3.laz");
    BEAMTRACE_REQUIRE_FILE(path);
    LasReader reader(path);
    EXPECT_EQ(reader.header().point_count, 0u);
    EXPECT_EQ(reader.header().point_format, 0);
    std::vector<LasPoint> points(4);
    EXPECT_EQ(reader.read(points), 0u);
}

TEST(LazReader, SeekLandsInsideAChunk) {
    // Layered chunks (COPC), point-wise chunks, and compressor 1's single stream.
    for (const char* name : {"las/laz/lone-star.copc.laz", "las/laz/autzen_trim.laz",
                             "las/edge/point-version-1-point-wise.laz"}) {
        SCOPED_TRACE(name);
        const fs::path path = test::shared_data(name);
        BEAMTRACE_REQUIRE_FILE(path);
        const std::vector<LasPoint> all = read_all(path, 1);
        LasReader reader(path, 2);
        for (const std::uint64_t at : {all.size() / 2 + 7, std::uint64_t{5}, all.size() - 3}) {
            reader.seek(at);
            std::vector<LasPoint> some(10);
            const std::size_t n = reader.read(some);
            ASSERT_EQ(n, std::min<std::size_t>(10, all.size() - at));
            for (std::size_t i = 0; i < n; ++i) {
                EXPECT_EQ(some[i], all[at + i]) << at + i;
            }
        }
    }
}

TEST(LazReader, OneAndTwoThreadsDecodeTheSamePoints) {
    const fs::path path = test::shared_data("las/laz/simple.copc.laz");
    BEAMTRACE_REQUIRE_FILE(path);
    EXPECT_EQ(read_all(path, 1), read_all(path, 2));
}

/// Copies `source` into the npm folder `lasval` (atomically: other tests may be running it).
fs::path install_script(const fs::path& lasval, const fs::path& source) {
    const fs::path script = lasval / source.filename();
    const fs::path staging = script.string() + "." + std::to_string(::getpid());
    fs::copy_file(source, staging, fs::copy_options::overwrite_existing);
    fs::rename(staging, script);
    return script;
}

/// The independent decode of `laz` as a LAS file (laz-perf and laz-rs must agree, else the
/// script refuses).
fs::path independent_las(const fs::path& lasval, const fs::path& laz, const fs::path& dir) {
    const fs::path script =
        install_script(lasval, test::shared_data("../tools/lasval/laz2las.mjs"));
    const fs::path out = dir / (laz.stem().string() + ".las");
    const auto r = test::run_command("cd '" + lasval.string() + "' && node '" + script.string() +
                                     "' '" + laz.string() + "' '" + out.string() + "' 2>&1");
    EXPECT_EQ(r.exit_code, 0) << r.out.substr(r.out.size() -
                                              std::min<std::size_t>(r.out.size(), 400));
    return out;
}

/// Our points must be laz-perf's decode of the raw records (COPC: laz-rs cannot open these).
void expect_same_as_laz_perf(const fs::path& lasval, const fs::path& laz, const fs::path& dir) {
    SCOPED_TRACE(laz.filename().string());
    const fs::path script = install_script(
        lasval, fs::path(BEAMTRACE_TEST_DATA_DIR).parent_path() / "laz" / "laz_records.mjs");
    const fs::path out = dir / (laz.stem().string() + ".records");
    const auto r = test::run_command("cd '" + lasval.string() + "' && node '" + script.string() +
                                     "' '" + laz.string() + "' '" + out.string() + "' 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out.substr(0, 400);
    const std::string records = test::read_file(out);
    LasReader reader(laz);
    const std::vector<LasPoint> ours = read_all(laz, 2);
    const std::size_t length = reader.header().point_record_length;
    ASSERT_EQ(records.size(), ours.size() * length);
    std::size_t differ = 0;
    LasPoint p;
    for (std::size_t i = 0; i < ours.size(); ++i) {
        reader.decode(reinterpret_cast<const std::uint8_t*>(records.data()) + i * length, p);
        differ += p == ours[i] ? 0 : 1;
    }
    EXPECT_EQ(differ, 0u);
}

TEST(LazReader, CopcFilesDecodeLikeLazPerf) {
    BEAMTRACE_REQUIRE_LASVAL(lasval);
    test::TempDir dir;
    for (const char* name : {"lone-star.copc.laz", "simple.copc.laz"}) {
        expect_same_as_laz_perf(lasval, test::shared_data(std::string("las/laz/") + name),
                                dir.path());
    }
}

TEST(LazReader, FilesWithoutTwinsDecodeLikeLazPerfAndLazRs) {
    BEAMTRACE_REQUIRE_LASVAL(lasval);
    test::TempDir dir;
    for (const char* name : {"las14_prf6.laz", "point10.las.laz", "point-time.las.laz",
                             "point-color.las.laz", "point-time-1.4.las.laz", "32-1-472-150-76.laz",
                             "dbh.laz", "MixedConifer.laz", "Topography.laz", "Megaplot.laz"}) {
        fs::path laz = test::shared_data(std::string("las/laz/") + name);
        if (std::string(name) == "32-1-472-150-76.laz") {
            // copc.js reads LAS 1.2 and 1.4 headers only; 1.1's is 1.2's.
            std::string bytes = test::read_file(laz);
            bytes[25] = 2;
            laz = test::write_file(dir / name, bytes);
        }
        const fs::path las = independent_las(lasval, laz, dir.path());
        if (fs::exists(las)) {
            expect_same_as(laz, las);
        }
    }
}

}  // namespace
}  // namespace beamtrace

namespace beamtrace {
namespace {

TEST(LazView, AutzenLazRendersPixelForPixelLikeItsLasTwin) {
    const fs::path las = test::shared_data("las/las/autzen_trim.las");
    const fs::path laz = test::shared_data("las/laz/autzen_trim.laz");
    BEAMTRACE_REQUIRE_FILE(laz);
    test::TempDir dir;
    std::string images[2];
    int k = 0;
    for (const fs::path& input : {las, laz}) {
        const fs::path png = dir / ("view" + std::to_string(k) + ".png");
        const auto r =
            test::run_command(std::string(BEAMTRACE_CLI_PATH) + " view '" + input.string() +
                              "' --camera 636237,849047,670,-25,-30 --fov 70 "
                              "--size 160x90 --color rgb --output '" +
                              png.string() + "' 2>&1");
        ASSERT_EQ(r.exit_code, 0) << r.out;
        images[k++] = test::read_file(png);
    }
    EXPECT_GT(images[0].size(), 1000u);
    EXPECT_EQ(images[0], images[1]);
}

}  // namespace
}  // namespace beamtrace
