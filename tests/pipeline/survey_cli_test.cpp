// `beamtrace survey` given bad input, through the CLI: every mistake exits 2 with one line that
// names the file at fault and the problem, and leaves nothing in the output folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "beamtrace/io/las_reader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr const char* kGoodScanner =
    "scanner: {type: rotating, preset: vlp16, duration_s: 0.1}\n"
    "platform: {type: static, position_m: [0, 0, 0]}\n";

constexpr const char* kFloor =
    "parts:\n  - plane: {point_m: [0, 0, -2], normal: [0, 0, 1], size_m: 40}\n";

/// Runs `beamtrace survey` on dir/survey.yaml into `out` (default dir/out).
test::RunResult run_survey_cli(const test::TempDir& dir, const std::string& extra = "",
                               std::string out = "") {
    if (out.empty()) {
        out = (dir / "out").string();
    }
    return test::run_command(extra + "'" + std::string(BEAMTRACE_CLI_PATH) + "' survey '" +
                             (dir / "survey.yaml").string() + "' --quiet --output '" + out + "'");
}

/// Expects exit status 2, exactly one line `beamtrace: error: ...` holding `fragment` (which
/// names the file at fault), and no entry at all in `out` (if it exists).
void expect_one_line_error(const test::RunResult& r, const std::string& fragment,
                           const std::filesystem::path& out) {
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_EQ(r.out.rfind("beamtrace: error: ", 0), 0u) << r.out;
    EXPECT_NE(r.out.find(fragment), std::string::npos) << "expected '" << fragment << "' in\n"
                                                       << r.out;
    if (std::filesystem::is_directory(out)) {
        EXPECT_EQ(test::entry_count(out), 0u) << "output left in " << out;
    }
}

struct BadSurvey {
    const char* what;
    std::string survey;    ///< survey.yaml
    std::string scene;     ///< scene.yaml ("" for none)
    std::string fragment;  ///< expected in the message, after the folder's path
};

TEST(SurveyCli, BadSurveyFilesExitTwoWithOneLineAndNoOutput) {
    const std::string scene = "scene: scene.yaml\n";
    const BadSurvey cases[] = {
        {"unknown key",
         scene + "scanner: {type: rotating, preset: vlp16, bogus: 1}\nplatform: {type: static}\n",
         kFloor, "survey.yaml:2: scanner.bogus: unknown key"},
        {"wrong type",
         scene + "scanner: {type: rotating, duration_s: soon}\nplatform: {type: static}\n", kFloor,
         "survey.yaml:2: scanner.duration_s: expected a number"},
        {"missing scene", kGoodScanner, "", "survey.yaml:1: scene: missing"},
        {"scene file not found", "scene: nowhere.yaml\n" + std::string(kGoodScanner), "",
         "survey.yaml:1: scene: file not found"},
        {"impossible sensor setting",
         scene + "scanner: {type: rotating, beam_elevations_deg: [-10, 100]}\n"
                 "platform: {type: static}\n",
         kFloor, "survey.yaml:2: scanner: beam_elevations_deg[1]"},
        {"point format", scene + kGoodScanner + "output: {point_format: 11}\n", kFloor,
         "survey.yaml:4: output.point_format: expected an integer in [4, 10]"},
        {"bad key in the scene", scene + kGoodScanner,
         "parts:\n  - plane: {point_m: [0, 0, -2], normal: [0, 0, 1], size_m: 40}\n"
         "    colour: red\n",
         "scene.yaml:3: parts[0].colour: unknown key"},
        {"unreadable mesh", scene + kGoodScanner, "parts:\n  - mesh: broken.obj\n", "broken.obj:3"},
        {"platform shorter than the scan",
         scene + "scanner: {type: line, duration_s: 5}\n"
                 "platform: {type: legs, speed_mps: 50, waypoints_m: [[0, 0, 9], [10, 0, 9]]}\n",
         kFloor, "survey.yaml: the scanner fires from 0"},
    };
    for (const BadSurvey& c : cases) {
        SCOPED_TRACE(c.what);
        test::TempDir dir;
        test::write_file(dir / "survey.yaml", c.survey);
        if (!c.scene.empty()) {
            test::write_file(dir / "scene.yaml", c.scene);
        }
        // Face 1 names vertex 7 of 2: out of range on line 3.
        test::write_file(dir / "broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
        expect_one_line_error(run_survey_cli(dir), dir.path().string() + "/" + c.fragment,
                              dir / "out");
        EXPECT_FALSE(std::filesystem::exists(dir / "out" / "points.las"));
    }
}

TEST(SurveyCli, BadTrajectoryFileIsNamedWithItsLine) {
    test::TempDir dir;
    test::write_file(dir / "scene.yaml", kFloor);
    test::write_file(dir / "poses.csv", "time_s,x,y,z,roll,pitch,yaw\n0,0,0,9,0,0,0\n1,0,0,9,0\n");
    test::write_file(dir / "survey.yaml",
                     "scene: scene.yaml\nscanner: {type: line, duration_s: 0.5}\n"
                     "platform: {type: trajectory, file: poses.csv}\n");
    expect_one_line_error(run_survey_cli(dir), (dir / "poses.csv").string() + ":3", dir / "out");
}

TEST(SurveyCli, OutputFolderThatIsAFileIsRefused) {
    test::TempDir dir;
    test::write_file(dir / "scene.yaml", kFloor);
    test::write_file(dir / "survey.yaml", "scene: scene.yaml\n" + std::string(kGoodScanner));
    test::write_file(dir / "taken", "a file\n");
    const auto r = run_survey_cli(dir, "", (dir / "taken").string());
    expect_one_line_error(r, (dir / "taken").string() + ": cannot create output directory",
                          dir / "taken");
    EXPECT_EQ(test::read_file(dir / "taken"), "a file\n");
}

TEST(SurveyCli, WriteFailureLeavesNoPartialOrTemporaryFiles) {
    // A file-size limit of 64 KiB (SIGXFSZ ignored, so writes fail with EFBIG) against a
    // ~0.9 MB LAS and CSV: the survey fails while writing, and must remove what it had begun.
    test::TempDir dir;
    test::write_file(dir / "scene.yaml", kFloor);
    test::write_file(dir / "survey.yaml",
                     "scene: scene.yaml\n" + std::string(kGoodScanner) + "output: {csv: true}\n");
    const auto r = run_survey_cli(dir, "trap '' XFSZ; ulimit -f 128; ");
    expect_one_line_error(r, (dir / "out").string(), dir / "out");
}

}  // namespace
}  // namespace beamtrace

namespace beamtrace {
namespace {

TEST(SurveyCli, MaxPulsesGivesTheFirstPointsOfTheFullRun) {
    test::TempDir dir;
    test::write_file(dir / "scene.yaml", kFloor);
    test::write_file(dir / "survey.yaml", std::string("scene: scene.yaml\n") + kGoodScanner);
    ASSERT_EQ(run_survey_cli(dir, "", (dir / "full").string()).exit_code, 0);
    const auto r = test::run_command(
        "'" + std::string(BEAMTRACE_CLI_PATH) + "' survey '" + (dir / "survey.yaml").string() +
        "' --quiet --max-pulses 5000 --output '" + (dir / "part").string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto full = read_las_points(dir / "full" / "points.las");
    const auto part = read_las_points(dir / "part" / "points.las");
    ASSERT_GT(part.size(), 1000u);
    ASSERT_LT(part.size(), full.size());
    for (std::size_t i = 0; i < part.size(); ++i) {
        ASSERT_EQ(part[i].x, full[i].x) << i;
        ASSERT_EQ(part[i].y, full[i].y) << i;
        ASSERT_EQ(part[i].gps_time, full[i].gps_time) << i;
    }
    // Every point of the full run after them comes from a later pulse.
    EXPECT_GT(full[part.size()].gps_time, part.back().gps_time);
}

}  // namespace
}  // namespace beamtrace
