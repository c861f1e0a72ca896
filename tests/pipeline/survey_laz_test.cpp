// The survey's points.laz (`output: {laz: true}`): the records of points.las LASzip-compressed,
// the same bytes at any thread count, `las: false` for LAZ alone, and refused with kept
// waveforms (LAZ formats 9 and 10 are not written).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHead = R"(scene: demo
scanner: {type: line, pulse_rate_hz: 20000, scan_rate_hz: 20, scan_angle_max_deg: 25,
          waveform: triangle, duration_s: 0.2}
platform: {type: legs, speed_mps: 50, waypoints_m: [[-30, 0, 150], [30, 0, 150]]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 2, rings: 1}
  returns: {mode: all, max: 5}
)";

SurveyResult run_in(const test::TempDir& dir, const std::string& yaml, unsigned threads,
                    const std::string& out) {
    test::write_file(dir / "survey.yaml", yaml);
    SurveyRunConfig run;
    run.output_dir = dir / out;
    run.threads = threads;
    run.chunk_pulses = 2048;
    return run_survey(load_survey_spec(dir / "survey.yaml"), run);
}

std::string records_of(const fs::path& path) {
    LasReader r(path);
    std::string bytes(r.header().point_count * r.header().point_record_length, '\0');
    EXPECT_EQ(
        r.read_records(std::span(reinterpret_cast<std::uint8_t*>(bytes.data()), bytes.size())),
        r.header().point_count);
    return bytes;
}

/// The file without its creation date (bytes 90-93 of the header).
std::string undated(const fs::path& path) {
    std::string bytes = test::read_file(path);
    bytes.replace(90, 4, 4, '\0');
    return bytes;
}

TEST(SurveyLaz, PointsLazHoldsThePointsOfPointsLasAtAnyThreadCount) {
    test::TempDir dir;
    const std::string yaml = std::string(kHead) + "output: {laz: true}\n";
    const SurveyResult one = run_in(dir, yaml, 1, "one");
    const SurveyResult two = run_in(dir, yaml, 2, "two");
    ASSERT_GT(one.points, 1000u);
    const fs::path laz = dir / "one" / "points.laz";
    ASSERT_TRUE(fs::exists(laz));
    ASSERT_TRUE(fs::exists(dir / "one" / "points.las"));
    EXPECT_EQ(one.outputs.size(), two.outputs.size());
    LasReader r(laz);
    EXPECT_TRUE(r.compressed());
    EXPECT_EQ(r.header().point_count, one.points);
    EXPECT_EQ(records_of(laz), records_of(dir / "one" / "points.las"));
    EXPECT_LT(fs::file_size(laz), fs::file_size(dir / "one" / "points.las"));
    EXPECT_TRUE(undated(laz) == undated(dir / "two" / "points.laz"));
}

TEST(SurveyLaz, LasFalseWritesLazAlone) {
    test::TempDir dir;
    const SurveyResult r =
        run_in(dir,
               std::string(kHead) +
                   "output: {las: false, laz: true, preview: false, trajectory_rate_hz: 0}\n",
               2, "out");
    EXPECT_FALSE(fs::exists(dir / "out" / "points.las"));
    ASSERT_TRUE(fs::exists(dir / "out" / "points.laz"));
    ASSERT_EQ(r.outputs.size(), 1u);
    EXPECT_EQ(r.outputs[0].filename(), "points.laz");
}

TEST(SurveyLaz, RefusedWithKeptWaveforms) {
    test::TempDir dir;
    const std::string yaml = std::string(kHead) + "  waveform: {keep: true}\noutput: {laz: true}\n";
    try {
        (void)parse_survey_spec(yaml, dir / "s.yaml");
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("output.laz: not with physics.waveform.keep: true"), std::string::npos)
            << what;
    }
    EXPECT_NO_THROW((void)parse_survey_spec(std::string(kHead) + "  waveform: {keep: true}\n"
                                                                 "output: {laz: false}\n",
                                            dir / "s.yaml"));
}

}  // namespace
}  // namespace beamtrace
