// `beamtrace bench`: in one run, the practical limit (Intel Embree called directly) on the rays
// of real surveys, our backends on the same rays, and the surveys end to end (LAS written), with
// scene load and build times and peak memory. Every figure is checked before it is timed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/cancel.hpp"

namespace beamtrace {

struct ThroughputBenchConfig {
    std::vector<std::filesystem::path> surveys;  ///< survey files (docs/survey.md)
    std::vector<unsigned> threads;               ///< empty: 1 and every hardware thread
    std::vector<BackendKind> backends;           ///< empty: embree (when built) and bvh
    std::size_t repeats = 3;       ///< every figure is the best of this many timed runs
    double min_time_s = 0.3;       ///< a trace measurement repeats its batch at least this long
    std::uint64_t max_pulses = 0;  ///< 0: whole surveys; else their first max_pulses pulses
    /// Where the surveys write (emptied); empty: a temporary folder of this process, removed
    /// at the end.
    std::filesystem::path scratch_dir;
    std::uint64_t seed = 1;
    /// Checked between steps and by the surveys (SurveyRunConfig::cancel): once requested, the
    /// benchmark stops, removes its scratch files and throws Interrupted. Null: runs to the end.
    const CancelToken* cancel = nullptr;

    /// Every problem (empty when usable).
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// One tracer's speed on a survey's rays.
struct TraceFigure {
    std::string tracer;  ///< "Embree rtcIntersect1", ..., or a backend name
    bool limit = false;  ///< a direct Embree call (a candidate for the limit)
    double rays_per_s = 0.0;
    /// Hits missing against the first tracer (rtcIntersect1): reported, not checked, for
    /// Embree's coherent mode, which is not watertight; 0 for every other tracer (checked).
    std::uint64_t missed_hits = 0;
};

/// The survey end to end with another backend than the default (the benchmark's other
/// `backends`), best run.
struct BackendSurveyFigure {
    std::string backend;
    double survey_s = 0.0;
    double pulses_per_s = 0.0;
    double points_per_s = 0.0;
};

struct ThreadFigures {
    unsigned threads = 1;
    std::vector<TraceFigure> trace;
    double survey_s = 0.0;  ///< survey stage (trace, physics, encode, write), best run
    double survey_pulses_per_s = 0.0;
    double survey_points_per_s = 0.0;
    std::vector<BackendSurveyFigure> other_backends;  ///< the same survey with each other backend
    double load_build_s = 0.0;       ///< scene load + build of the default backend, best run
    std::size_t peak_rss_bytes = 0;  ///< highest peak RSS of the end-to-end runs
    [[nodiscard]] double limit_rays_per_s() const;  ///< the fastest direct Embree call
};

struct SurveyBenchResult {
    std::string name;  ///< the survey file's stem
    std::uint64_t triangles = 0, stored_triangles = 0;
    std::uint64_t pulses = 0, rays = 0, hits = 0, points = 0;
    std::vector<ThreadFigures> runs;  ///< one per thread count
};

struct ThroughputReport {
    std::string machine;  ///< CPU model and hardware threads
    std::string backend;  ///< the backend of the end-to-end surveys (the default)
    /// True when each end-to-end memory run ran in a child process of its own (its peak RSS is
    /// the survey's alone); false when it ran in this process (a process with other threads),
    /// on top of what the process held.
    bool memory_isolated = false;
    std::vector<SurveyBenchResult> surveys;
};

/// Runs the benchmark; `log` (optional) gets a line per step. Throws ConfigError for bad
/// settings or survey files, and std::runtime_error when a check fails (tracers disagree on the
/// hits, the survey's LAS file does not hold its points), and Interrupted (config.cancel).
[[nodiscard]] ThroughputReport run_throughput_bench(
    const ThroughputBenchConfig& config, const std::function<void(const std::string&)>& log = {});

/// The report as Markdown tables: rays/s per tracer and survey points/s, with ratios to the
/// limit, plus the 1 -> N thread scaling.
[[nodiscard]] std::string format_throughput_report(const ThroughputReport& report);

}  // namespace beamtrace
