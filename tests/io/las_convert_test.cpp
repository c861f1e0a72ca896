// convert_las: LAS -> LAZ -> LAS gives back the original bytes (real files of every LAS version
// and of formats 0-10), LAZ written by LASzip decodes to its records, VLRs and EVLRs, the LAZ of
// a LAS file we wrote is the file LasWriter writes as LAZ, the same bytes at any thread count;
// laz-perf and laz-rs decode our LAZ of real files to the originals.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_convert.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "io/independent_las.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

LasConvertConfig to(LasCompression c, unsigned threads = 2, std::uint32_t chunk = 50000) {
    LasConvertConfig config;
    config.compression = c;
    config.threads = threads;
    config.laz_chunk_size = chunk;
    return config;
}

std::string records_of(const fs::path& path) {
    LasReader r(path);
    std::string bytes(r.header().point_count * r.header().point_record_length, '\0');
    EXPECT_EQ(
        r.read_records(std::span(reinterpret_cast<std::uint8_t*>(bytes.data()), bytes.size())),
        r.header().point_count);
    return bytes;
}

/// The VLRs and EVLRs but the LASzip one.
std::vector<LasVlr> vlrs_of(const fs::path& path) {
    LasReader r(path);
    std::vector<LasVlr> v;
    for (const LasVlr& x : r.vlrs()) {
        if (!(x.user_id == "laszip encoded" && x.record_id == 22204)) {
            v.push_back(x);
        }
    }
    return v;
}

void expect_same_vlrs(const std::vector<LasVlr>& a, const std::vector<LasVlr>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].user_id, b[i].user_id) << i;
        EXPECT_EQ(a[i].record_id, b[i].record_id) << i;
        EXPECT_EQ(a[i].description, b[i].description) << i;
        EXPECT_EQ(a[i].data, b[i].data) << i;
        EXPECT_EQ(a[i].length, b[i].length) << i;
        EXPECT_EQ(a[i].extended, b[i].extended) << i;
    }
}

const char* const kLasFiles[] = {
    "simple.las",      "simple1_1.las",     "simple1_3.las",
    "simple1_4.las",   "test1_4.las",       "point-color.las",
    "autzen_trim.las", "autzen_trim_7.las", "point-version-1-point-wise.las"};

TEST(LasConvert, LasToLazToLasGivesTheSameBytes) {
    test::TempDir dir;
    for (const char* name : kLasFiles) {
        SCOPED_TRACE(name);
        const fs::path las = test::shared_data(std::string("las/las/") + name);
        BEAMTRACE_REQUIRE_FILE(las);
        const auto r = convert_las(las, dir / "a.laz", to(LasCompression::laz));
        EXPECT_FALSE(r.input_compressed);
        EXPECT_LT(r.output_bytes, r.input_bytes);
        LasReader laz(dir / "a.laz");
        EXPECT_TRUE(laz.compressed());
        EXPECT_EQ(r.points, laz.header().point_count);
        EXPECT_EQ(records_of(dir / "a.laz"), records_of(las));
        expect_same_vlrs(vlrs_of(dir / "a.laz"), vlrs_of(las));
        (void)convert_las(dir / "a.laz", dir / "b.las", to(LasCompression::none));
        EXPECT_TRUE(test::read_file(dir / "b.las") == test::read_file(las));
    }
}

TEST(LasConvert, LaszipFilesDecodeToTheirRecordsVlrsAndEvlrs) {
    test::TempDir dir;
    for (const char* name : {"1_4_w_evlr.laz", "extra.laz", "fwf.laz", "las14_prf6.laz",
                             "simple.laz", "point10.las.laz", "simple.copc.laz"}) {
        SCOPED_TRACE(name);
        const fs::path laz = test::shared_data(std::string("las/laz/") + name);
        BEAMTRACE_REQUIRE_FILE(laz);
        const auto r = convert_las(laz, dir / "a.las", to(LasCompression::none));
        EXPECT_TRUE(r.input_compressed);
        LasReader in(laz), out(dir / "a.las");
        EXPECT_FALSE(out.compressed());
        EXPECT_EQ(out.header().point_format, in.header().point_format);
        EXPECT_EQ(out.header().point_count, in.header().point_count);
        EXPECT_EQ(out.header().number_of_evlrs, in.header().number_of_evlrs);
        EXPECT_EQ(out.header().number_of_vlrs + 1, in.header().number_of_vlrs);
        EXPECT_EQ(records_of(dir / "a.las"), records_of(laz));
        expect_same_vlrs(vlrs_of(dir / "a.las"), vlrs_of(laz));
        (void)convert_las(dir / "a.las", dir / "b.laz", to(LasCompression::laz, 3));
        (void)convert_las(dir / "b.laz", dir / "c.las", to(LasCompression::none, 1));
        EXPECT_TRUE(test::read_file(dir / "c.las") == test::read_file(dir / "a.las"));
    }
}

LasWriterConfig writer_config(LasCompression c) {
    LasWriterConfig config;
    config.point_format = 7;
    config.extra_bytes_per_point = 2;
    config.creation_year = 2026;
    config.creation_day_of_year = 1;
    config.compression = c;
    config.threads = 2;
    LasVlr e;
    e.user_id = "beamtrace";
    e.record_id = 9;
    e.data.assign(1000, 7);
    e.extended = true;
    config.vlrs.push_back(e);
    return config;
}

fs::path write_points(const fs::path& path, LasCompression c) {
    LasWriter w(path, writer_config(c));
    std::vector<LasPoint> points(120000);
    for (std::size_t i = 0; i < points.size(); ++i) {
        LasPoint& p = points[i];
        p.x = 0.001 * static_cast<double>(i % 7000);
        p.y = 0.002 * static_cast<double>(i / 7000);
        p.z = 0.001 * static_cast<double>((i * 31) % 1000);
        p.gps_time = 1000.0 + 1e-4 * static_cast<double>(i);
        p.intensity = static_cast<std::uint16_t>(i * 13);
        p.return_number = p.number_of_returns = 1;
        p.red = static_cast<std::uint16_t>(i);
        p.extra_bytes = {static_cast<std::uint8_t>(i), 3};
    }
    w.write(points);
    w.close();
    return path;
}

TEST(LasConvert, OurLasBecomesTheLazLasWriterWrites) {
    test::TempDir dir;
    const fs::path las = write_points(dir / "w.las", LasCompression::none);
    const fs::path laz = write_points(dir / "w.laz", LasCompression::laz);
    (void)convert_las(las, dir / "c.laz", to(LasCompression::laz, 1));
    EXPECT_TRUE(test::read_file(dir / "c.laz") == test::read_file(laz));
    (void)convert_las(laz, dir / "c.las", to(LasCompression::none, 1));
    EXPECT_TRUE(test::read_file(dir / "c.las") == test::read_file(las));
}

TEST(LasConvert, TheSameBytesAtAnyThreadCount) {
    test::TempDir dir;
    const fs::path las = test::shared_data("las/las/autzen_trim.las");
    BEAMTRACE_REQUIRE_FILE(las);
    (void)convert_las(las, dir / "1.laz", to(LasCompression::laz, 1, 7777));
    for (const unsigned threads : {2u, 5u, 0u}) {
        (void)convert_las(las, dir / "n.laz", to(LasCompression::laz, threads, 7777));
        EXPECT_TRUE(test::read_file(dir / "n.laz") == test::read_file(dir / "1.laz")) << threads;
    }
}

TEST(LasConvert, BadInputNamesTheFileAndWritesNothing) {
    test::TempDir dir;
    const fs::path bad = test::write_file(dir / "bad.las", std::string("LASF not really"));
    try {
        (void)convert_las(bad, dir / "out.laz", to(LasCompression::laz));
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("bad.las"), std::string::npos) << e.what();
    }
    EXPECT_THROW((void)convert_las(dir / "none.las", dir / "out.laz", to(LasCompression::laz)),
                 InputError);
    EXPECT_FALSE(fs::exists(dir / "out.laz"));
    EXPECT_EQ(test::entry_count(dir.path()), 1u);  // no temporary file either
}

TEST(LasConvert, LazPerfAndLazRsDecodeOurLazToTheOriginal) {
    BEAMTRACE_REQUIRE_LASVAL(lasval);
    test::TempDir dir;
    const fs::path script = lasval / "laz2las.mjs";
    const fs::path staging = script.string() + "." + std::to_string(::getpid());
    fs::copy_file(test::shared_data("../tools/lasval/laz2las.mjs"), staging,
                  fs::copy_options::overwrite_existing);
    fs::rename(staging, script);
    // copc.js reads LAS 1.2 and 1.4 headers only.
    for (const char* name :
         {"simple.las", "point-color.las", "test1_4.las", "autzen_trim.las", "autzen_trim_7.las"}) {
        SCOPED_TRACE(name);
        const fs::path las = test::shared_data(std::string("las/las/") + name);
        BEAMTRACE_REQUIRE_FILE(las);
        (void)convert_las(las, dir / "a.laz", to(LasCompression::laz));
        const auto r =
            test::run_command("cd '" + lasval.string() + "' && node '" + script.string() + "' '" +
                              (dir / "a.laz").string() + "' '" + (dir / "b.las").string() + "'");
        ASSERT_EQ(r.exit_code, 0) << r.out.substr(r.out.size() -
                                                  std::min<std::size_t>(r.out.size(), 600));
        EXPECT_TRUE(test::read_file(dir / "b.las") == test::read_file(las));
    }
}

}  // namespace
}  // namespace beamtrace
