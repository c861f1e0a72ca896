// Cancellation in the library: a CancelToken requested before or during run_survey / run_scan
// makes them throw Interrupted and leave the output directory as it was.
#include <gtest/gtest.h>

#include <csignal>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/core/cancel.hpp"
#include "beamtrace/pipeline/scan_job.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr const char* kSurvey = R"(scene: demo
scanner: {type: rotating, preset: hdl32, duration_s: 0.1}
platform: {type: legs, speed_mps: 10, waypoints_m: [[-10, -10, 2], [10, -10, 3]]}
output: {csv: true, ply: true}
)";

std::set<std::string> names_in(const std::filesystem::path& dir) {
    std::set<std::string> names;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        names.insert(e.path().filename().string());
    }
    return names;
}

/// Whether `dir` holds a temporary file (`.NAME.PID.tmp`).
bool has_temporaries(const std::filesystem::path& dir) {
    for (const auto& name : names_in(dir)) {
        if (name.front() == '.' && name.ends_with(".tmp")) {
            return true;
        }
    }
    return false;
}

SurveySpec demo_survey(const test::TempDir& dir) {
    test::write_file(dir / "survey.yaml", kSurvey);
    return load_survey_spec(dir / "survey.yaml");
}

TEST(CancelToken, KeepsTheFirstReason) {
    CancelToken token;
    EXPECT_FALSE(token.requested());
    EXPECT_EQ(token.reason(), 0);
    EXPECT_NO_THROW(throw_if_cancelled(&token, "x"));
    EXPECT_NO_THROW(throw_if_cancelled(nullptr, "x"));
    token.request(SIGTERM);
    token.request(SIGINT);
    EXPECT_TRUE(token.requested());
    EXPECT_EQ(token.reason(), SIGTERM);
    try {
        throw_if_cancelled(&token, "survey");
        FAIL() << "no Interrupted";
    } catch (const Interrupted& e) {
        EXPECT_EQ(e.reason(), SIGTERM);
        EXPECT_STREQ(e.what(), "survey: interrupted; nothing was written");
    }
    CancelToken zero;
    zero.request(0);
    EXPECT_EQ(zero.reason(), 1);  // 0 would read as "not requested"
}

TEST(SurveyProgress, ReportsStartWhenTheSurveyStageStartsAndEndAtTheTotal) {
    // The CLI's rate counts from the first report (done = 0): loading and building the scene
    // before it are not in the rate.
    test::TempDir dir;
    const SurveySpec spec = demo_survey(dir);
    SurveyRunConfig run;
    run.output_dir = dir / "out";
    run.threads = 2;
    run.chunk_pulses = 2048;
    std::vector<std::pair<std::size_t, std::size_t>> reports;
    (void)run_survey(
        spec, run, [&](std::size_t done, std::size_t total) { reports.emplace_back(done, total); });
    ASSERT_GE(reports.size(), 3u);
    EXPECT_EQ(reports.front().first, 0u);
    const std::size_t total = reports.front().second;
    EXPECT_GT(total, 0u);
    for (std::size_t i = 1; i < reports.size(); ++i) {
        EXPECT_GT(reports[i].first, reports[i - 1].first) << i;
        EXPECT_EQ(reports[i].second, total) << i;
    }
    EXPECT_EQ(reports.back().first, total);
}

TEST(SurveyCancel, RequestedBeforeTheRunWritesNothing) {
    test::TempDir dir;
    const SurveySpec spec = demo_survey(dir);
    CancelToken token;
    token.request(SIGINT);
    SurveyRunConfig run;
    run.output_dir = dir / "out" / "nested";
    run.cancel = &token;
    EXPECT_THROW((void)run_survey(spec, run), Interrupted);
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

/// Runs the survey into `out` and requests the token at the `at`-th progress report.
void cancel_at_progress(const SurveySpec& spec, const std::filesystem::path& out, int at) {
    CancelToken token;
    SurveyRunConfig run;
    run.output_dir = out;
    run.threads = 2;
    run.chunk_pulses = 2048;  // a progress report every block or two
    run.cancel = &token;
    int reports = 0;
    bool temporaries_seen = false;
    try {
        (void)run_survey(spec, run, [&](std::size_t, std::size_t) {
            if (++reports == at) {
                // The sinks are writing: their temporary files are there now.
                temporaries_seen = has_temporaries(out);
                token.request(SIGTERM);
            }
        });
        FAIL() << "the survey ran to the end";
    } catch (const Interrupted& e) {
        EXPECT_EQ(e.reason(), SIGTERM);
    }
    EXPECT_TRUE(temporaries_seen);
    EXPECT_EQ(reports, at) << "the survey went on after the request";
}

TEST(SurveyCancel, RequestedDuringTheRunLeavesTheDirectoryAsItWas) {
    test::TempDir dir;
    const SurveySpec spec = demo_survey(dir);
    std::filesystem::create_directories(dir / "out");
    test::write_file(dir / "out" / "keep.txt", "mine");
    for (const int at : {1, 3}) {
        cancel_at_progress(spec, dir / "out", at);
        EXPECT_EQ(names_in(dir / "out"), std::set<std::string>{"keep.txt"});
        EXPECT_EQ(test::read_file(dir / "out" / "keep.txt"), "mine");
    }
}

TEST(SurveyCancel, RemovesTheDirectoriesItCreated) {
    test::TempDir dir;
    const SurveySpec spec = demo_survey(dir);
    cancel_at_progress(spec, dir / "a" / "b", 2);
    EXPECT_FALSE(std::filesystem::exists(dir / "a"));
    EXPECT_EQ(names_in(dir.path()), std::set<std::string>{"survey.yaml"});
}

TEST(SurveyCancel, WithoutARequestTheTokenChangesNothing) {
    test::TempDir a, b;
    const SurveySpec spec = demo_survey(a);
    CancelToken token;
    SurveyRunConfig run;
    run.output_dir = a / "out";
    (void)run_survey(spec, run);
    run.output_dir = b / "out";
    run.cancel = &token;
    (void)run_survey(spec, run);
    for (const char* f : {"points.las", "points.csv", "points.ply", "trajectory.csv"}) {
        EXPECT_EQ(test::read_file(a / "out" / f), test::read_file(b / "out" / f)) << f;
    }
}

ScanJobConfig demo_scan(const std::filesystem::path& out, const CancelToken& token) {
    ScanJobConfig c;
    c.demo = true;
    c.apply({});
    c.sensor.width = 400;
    c.sensor.height = 400;  // 160000 rays: three chunks
    c.threads = 2;
    c.output_dir = out;
    c.cancel = &token;
    c.outputs = parse_scan_outputs("ply,npy,png,csv");
    return c;
}

TEST(ScanCancel, RequestedWhileTracingOrWritingLeavesNothing) {
    test::TempDir dir;
    std::filesystem::create_directories(dir / "out");
    test::write_file(dir / "out" / "keep.txt", "mine");
    // While tracing (first chunk), and after the last chunk: then the write loop stops.
    for (const bool at_end : {false, true}) {
        CancelToken token;
        const ScanJobConfig c = demo_scan(dir / "out", token);
        std::size_t reports = 0;
        EXPECT_THROW((void)run_scan(c,
                                    [&](std::size_t done, std::size_t total) {
                                        ++reports;
                                        if (!at_end || done == total) {
                                            token.request(SIGINT);
                                        }
                                    }),
                     Interrupted);
        EXPECT_EQ(reports, at_end ? 4u : 1u);  // the start (done 0), then 3 chunks
        EXPECT_EQ(names_in(dir / "out"), std::set<std::string>{"keep.txt"});
    }
    CancelToken token;
    const ScanJobConfig c = demo_scan(dir / "new", token);
    token.request(SIGINT);
    EXPECT_THROW((void)run_scan(c), Interrupted);
    EXPECT_FALSE(std::filesystem::exists(dir / "new"));
}

TEST(ScanCancel, WithoutARequestAllOutputsAreWritten) {
    test::TempDir dir;
    CancelToken token;
    const ScanResult r = run_scan(demo_scan(dir / "out", token));
    EXPECT_EQ(names_in(dir / "out"),
              (std::set<std::string>{"hits.csv", "points.ply", "range.npy", "range.png"}));
    ASSERT_FALSE(r.outputs.empty());
    EXPECT_EQ(r.outputs.front().filename(), "points.ply");  // in the order of --outputs' names
}

}  // namespace
}  // namespace beamtrace
