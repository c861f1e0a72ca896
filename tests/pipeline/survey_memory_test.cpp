// The survey's in-memory output: SurveyRunConfig::extra_sinks with the callback sink gets the
// points of points.las (the same values, in file order) with or without the file outputs, and
// write_files = false writes nothing and needs no output directory.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/communicator.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/callback_sink.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/pipeline/survey_distributed.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

// Physics (sub-rays, noise, several returns a pulse), several blocks of 1024 pulses.
constexpr const char* kSurvey = R"(scene: demo
scanner: {type: line, pulse_rate_hz: 20000, scan_rate_hz: 40, scan_angle_max_deg: 25,
          waveform: triangle, duration_s: 0.2}
platform: {type: legs, speed_mps: 50, waypoints_m: [[-30, 0, 150], [30, 0, 150]]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 2, rings: 1}
  noise: {range_sigma_m: 0.02}
  returns: {mode: all, max: 5}
)";

/// Runs kSurvey with a callback sink collecting the points; files into `out` unless empty.
std::vector<BlockPoint> run_collecting(const test::TempDir& dir, const fs::path& out,
                                       unsigned threads, SurveyResult* result = nullptr) {
    test::write_file(dir / "survey.yaml", kSurvey);
    std::vector<BlockPoint> points;
    SurveyRunConfig run;
    run.threads = threads;
    run.chunk_pulses = 2048;
    run.seed = 5;
    run.output_dir = out;
    run.write_files = !out.empty();
    run.extra_sinks.emplace_back([&points](const SinkFacts& facts) {
        return make_callback_sink(facts, [&points](std::span<const BlockPoint> block) {
            points.insert(points.end(), block.begin(), block.end());
        });
    });
    const SurveyResult r = run_survey(load_survey_spec(dir / "survey.yaml"), run);
    if (result != nullptr) {
        *result = r;
    }
    return points;
}

void expect_same_as_las(const std::vector<BlockPoint>& points, const std::vector<LasPoint>& las) {
    ASSERT_EQ(points.size(), las.size());
    for (std::size_t i = 0; i < las.size(); ++i) {
        const BlockPoint& p = points[i];
        const LasPoint& q = las[i];
        ASSERT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << "point " << i;
        ASSERT_EQ(p.scan_angle_deg, q.scan_angle_deg) << "point " << i;
        ASSERT_EQ(p.gps_time, q.gps_time) << "point " << i;
        ASSERT_EQ(p.intensity, q.intensity) << "point " << i;
        ASSERT_EQ(p.return_number, q.return_number) << "point " << i;
        ASSERT_EQ(p.number_of_returns, q.number_of_returns) << "point " << i;
        ASSERT_EQ(p.classification, q.classification) << "point " << i;
        ASSERT_EQ(p.point_source_id, q.point_source_id) << "point " << i;
        ASSERT_EQ(p.user_data, q.user_data) << "point " << i;
    }
}

TEST(SurveyMemory, CallbackPointsEqualPointsLasWithAndWithoutFiles) {
    test::TempDir dir;
    SurveyResult result;
    const auto with_files = run_collecting(dir, dir / "out", 2, &result);
    const std::vector<LasPoint> las = read_las_points(dir / "out" / "points.las");
    ASSERT_GT(las.size(), 3000u);
    EXPECT_EQ(result.points, las.size());
    expect_same_as_las(with_files, las);
    // Pulses with several returns: their order within a pulse is kept too.
    EXPECT_TRUE(std::any_of(las.begin(), las.end(),
                            [](const LasPoint& p) { return p.number_of_returns > 1; }));

    const auto memory_only = run_collecting(dir, {}, 1, &result);
    EXPECT_EQ(result.points, las.size());
    EXPECT_TRUE(result.outputs.empty());
    expect_same_as_las(memory_only, las);
}

TEST(SurveyMemory, WithoutFilesNothingIsWrittenAndNoFolderIsNeeded) {
    test::TempDir dir;
    const fs::path cwd = fs::current_path();
    fs::current_path(dir.path());  // where a file with an empty output_dir would land
    const auto points = run_collecting(dir, {}, 2);
    fs::current_path(cwd);
    EXPECT_GT(points.size(), 3000u);
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir.path())) {
        names.push_back(e.path().filename().string());
    }
    EXPECT_EQ(names, std::vector<std::string>{"survey.yaml"});
}

TEST(SurveyMemory, FilesStillNeedAnOutputDirectory) {
    test::TempDir dir;
    test::write_file(dir / "survey.yaml", kSurvey);
    SurveyRunConfig run;  // write_files, no output_dir
    EXPECT_THROW((void)run_survey(load_survey_spec(dir / "survey.yaml"), run), ConfigError);
}

TEST(SurveyMemory, SurveysAcrossProcessesRefuseExtraSinks) {
    test::TempDir dir;
    test::write_file(dir / "survey.yaml", kSurvey);
    const SurveySpec spec = load_survey_spec(dir / "survey.yaml");
    SurveyRunConfig run;
    run.output_dir = dir / "out";
    run.extra_sinks.emplace_back([](const SinkFacts& facts) {
        return make_callback_sink(facts, [](std::span<const BlockPoint>) {});
    });
    const auto solo = solo_communicator();
    EXPECT_THROW((void)run_survey_distributed(spec, run, *solo), ConfigError);
    run.extra_sinks.clear();
    run.write_files = false;
    EXPECT_THROW((void)run_survey_distributed(spec, run, *solo), ConfigError);
    EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace beamtrace
