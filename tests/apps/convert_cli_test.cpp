// `beamtrace convert IN OUT`: LAS -> LAZ -> LAS through the CLI gives the original bytes and a
// summary line; a bad input, an unknown extension or a bad chunk size exit 2 with one line
// naming the problem and write nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "beamtrace/io/las_reader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

test::RunResult convert(const std::string& args) {
    return test::run_command(std::string(BEAMTRACE_CLI_PATH) + " convert " + args);
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(ConvertCli, LasToLazAndBackGivesTheOriginal) {
    const fs::path las = test::shared_data("las/las/autzen_trim.las");
    BEAMTRACE_REQUIRE_FILE(las);
    test::TempDir dir;
    const fs::path laz = dir / "a.LAZ";
    auto r = convert("'" + las.string() + "' '" + laz.string() + "' --threads 2 --chunk-size 9999");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(has(r.out, "(LAS, 3742038 bytes) -> ")) << r.out;
    EXPECT_TRUE(has(r.out, "(LAZ, ")) << r.out;
    EXPECT_TRUE(has(r.out, ": 110000 points")) << r.out;
    EXPECT_LT(fs::file_size(laz), fs::file_size(las) / 4);
    r = convert("--quiet '" + laz.string() + "' '" + (dir / "b.las").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(r.out, "");
    EXPECT_TRUE(test::read_file(dir / "b.las") == test::read_file(las));
}

TEST(ConvertCli, ErrorsExit2AndWriteNothing) {
    const fs::path las = test::shared_data("las/las/simple.las");
    BEAMTRACE_REQUIRE_FILE(las);
    test::TempDir dir;
    const fs::path garbage = test::write_file(dir / "garbage.laz", std::string(400, 'x'));
    struct Case {
        std::string args, expected;
    };
    const Case cases[] = {
        {"'" + las.string() + "' '" + (dir / "out.txt").string() + "'",
         "unknown extension '.txt' (expected .las or .laz)"},
        {"'" + (dir / "missing.las").string() + "' '" + (dir / "out.laz").string() + "'",
         "missing.las: cannot open"},
        {"'" + garbage.string() + "' '" + (dir / "out.las").string() + "'",
         "garbage.laz: header: bad file signature"},
        {"'" + las.string() + "' '" + (dir / "out.laz").string() + "' --chunk-size 0",
         "--chunk-size 0 (expected 1 to 4294967294 points)"},
        {"'" + las.string() + "' '" + (dir / "no" / "such" / "out.laz").string() + "'", "out.laz"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const auto r = convert(c.args);
        EXPECT_EQ(r.exit_code, 2) << r.out;
        EXPECT_TRUE(has(r.out, "beamtrace: error: ")) << r.out;
        EXPECT_TRUE(has(r.out, c.expected)) << r.out;
    }
    EXPECT_EQ(test::entry_count(dir.path()), 1u);  // the garbage input only
}

}  // namespace
}  // namespace beamtrace

namespace beamtrace {
namespace {

// `beamtrace scan --laz`: points.laz holds the points of points.ply.
TEST(ScanLazCli, PointsLazHoldsThePointsOfPointsPly) {
    test::TempDir dir;
    const auto r = test::run_command(std::string(BEAMTRACE_CLI_PATH) +
                                     " scan --demo --laz --quiet --threads 2 --output '" +
                                     (dir / "out").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const std::string ply = test::read_file(dir / "out" / "points.ply");
    const auto at = ply.find("element vertex ");
    ASSERT_NE(at, std::string::npos);
    const std::uint64_t vertices = std::stoull(ply.substr(at + 15));
    LasReader laz(dir / "out" / "points.laz");
    EXPECT_TRUE(laz.compressed());
    EXPECT_EQ(laz.header().point_count, vertices);
    EXPECT_EQ(laz.header().points_by_return[0], vertices);
    std::vector<LasPoint> first(1);
    ASSERT_EQ(laz.read(first), 1u);
    EXPECT_EQ(first[0].return_number, 1);
}

}  // namespace
}  // namespace beamtrace
