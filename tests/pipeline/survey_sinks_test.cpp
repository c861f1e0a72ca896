// The survey's outputs through the sink registry: `output:` keys come from the table (pcd is
// one), every output of a run is listed and identical at any thread count, and a sink failing
// at the end leaves none of the run's files.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSurvey = R"(scene: demo
scanner: {type: line, pulse_rate_hz: 20000, scan_rate_hz: 20, scan_angle_max_deg: 25,
          waveform: triangle, duration_s: 0.1}
platform: {type: legs, speed_mps: 50, waypoints_m: [[-30, 0, 150], [30, 0, 150]]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 2, rings: 1}
  returns: {mode: all, max: 5}
  waveform: {keep: true}
output: {pcd: true, ply: true, csv: true, trajectory_rate_hz: 10}
)";

SurveyResult run_in(const test::TempDir& dir, const std::string& yaml, unsigned threads,
                    const std::string& out = "out") {
    test::write_file(dir / "survey.yaml", yaml);
    SurveyRunConfig run;
    run.output_dir = dir / out;
    run.threads = threads;
    run.chunk_pulses = 2048;
    return run_survey(load_survey_spec(dir / "survey.yaml"), run);
}

std::set<std::string> files_in(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) {
        names.insert(e.path().filename().string());
    }
    return names;
}

TEST(SurveySinks, EveryOutputIsListedInRegistryOrderAndIdenticalAtAnyThreadCount) {
    test::TempDir dir;
    const SurveyResult one = run_in(dir, kSurvey, 1, "one");
    const SurveyResult two = run_in(dir, kSurvey, 2, "two");
    std::vector<std::string> names;
    for (const auto& f : one.outputs) {
        names.push_back(f.filename().string());
    }
    EXPECT_EQ(names, (std::vector<std::string>{"points.las", "points.wdp", "waveforms.bin",
                                               "points.csv", "points.ply", "trajectory.csv",
                                               "points.pcd", "preview.png"}));
    EXPECT_EQ(files_in(dir / "one"), std::set<std::string>(names.begin(), names.end()));
    ASSERT_EQ(two.outputs.size(), one.outputs.size());
    for (const std::string& n : names) {
        if (n != "points.las") {  // the LAS header holds the creation date
            EXPECT_EQ(test::read_file(dir / "one" / n), test::read_file(dir / "two" / n)) << n;
        }
    }
    EXPECT_GT(one.points, 1000u);
}

TEST(SurveySinks, OutputKeysComeFromTheRegistry) {
    test::TempDir dir;
    const std::string head = std::string(kSurvey).substr(0, std::string(kSurvey).find("output:"));
    EXPECT_NO_THROW(
        (void)parse_survey_spec(head + "output: {pcd: false, ply: true}\n", dir / "s.yaml"));
    const SurveySpec spec =
        parse_survey_spec(head + "output: {pcd: true, csv: true}\n", dir / "s.yaml");
    EXPECT_EQ(spec.outputs, (std::vector<std::string>{"las", "preview", "csv", "pcd"}));
    EXPECT_EQ(parse_survey_spec(head + "output: {preview: false}\n", dir / "s.yaml").outputs,
              std::vector<std::string>{"las"});
    try {
        (void)parse_survey_spec(head + "output: {pcd: 3, lazz: true}\n", dir / "s.yaml");
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("output.pcd: expected true or false"), std::string::npos) << what;
        EXPECT_NE(what.find("output.lazz: unknown key (expected one of: point_format, "
                            "trajectory_rate_hz, wave_packets, extra_bytes, point_source_id, "
                            "las, laz, csv, ply, pcd, preview, no_echo)"),
                  std::string::npos)
            << what;
    }
}

TEST(SurveySinks, ASinkFailingAtTheEndLeavesNoneOfTheRunsFiles) {
    test::TempDir dir;
    // A folder where points.csv should go: the CSV sink's rename fails after points.las and
    // waveforms.bin were committed.
    fs::create_directories(dir / "out" / "points.csv");
    EXPECT_THROW((void)run_in(dir, kSurvey, 2), OutputError);
    EXPECT_EQ(files_in(dir / "out"), std::set<std::string>{"points.csv"});
    EXPECT_TRUE(fs::is_empty(dir / "out" / "points.csv"));
}

}  // namespace
}  // namespace beamtrace
