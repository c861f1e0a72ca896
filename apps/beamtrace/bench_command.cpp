#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "commands.hpp"
#include "harness/throughput_bench.hpp"

namespace beamtrace::cli {
namespace {

struct BenchOptions {
    std::vector<std::string> surveys;
    std::vector<unsigned> threads;
    std::vector<std::string> backends;
    std::size_t repeats = 3;
    double min_time_s = 0.3;
    std::uint64_t pulses = 0;
    std::string output;
    bool quiet = false;
};

/// The surveys `beamtrace bench` runs by default, relative to the repository root: terrestrial
/// (a tripod panorama), airborne (line scanner over the 1.48 M-triangle SRTM DEM) and a
/// 64-beam spinning scanner on a car.
const char* const kDefaultSurveys[] = {"examples/surveys/tripod_panorama.yaml",
                                       "examples/surveys/airborne_srtm.yaml",
                                       "examples/surveys/car_hdl64.yaml"};

int run(const BenchOptions& o) {
    ThroughputBenchConfig c;
    if (o.surveys.empty()) {
        for (const char* s : kDefaultSurveys) {
            if (!std::filesystem::exists(s)) {
                throw ConfigError(std::string(s) +
                                  ": not found; run `beamtrace bench` from the repository root "
                                  "or name survey files");
            }
            c.surveys.emplace_back(s);
        }
    } else {
        c.surveys.assign(o.surveys.begin(), o.surveys.end());
    }
    c.threads = o.threads;
    for (const auto& b : o.backends) {
        c.backends.push_back(parse_backend_kind(b));
    }
    c.repeats = o.repeats;
    c.min_time_s = o.min_time_s;
    c.max_pulses = o.pulses;
    const ThroughputReport report = run_throughput_bench(c, [&](const std::string& line) {
        if (!o.quiet) {
            std::fprintf(stderr, "bench: %s\n", line.c_str());
        }
    });
    const std::string text = format_throughput_report(report);
    std::fputs(text.c_str(), stdout);
    if (!o.output.empty()) {
        AtomicFile file(o.output);
        file.write(text);
        file.commit();
    }
    return 0;
}

}  // namespace

std::function<int()> add_bench_command(CLI::App& app) {
    auto opts = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand(
        "bench",
        "Throughput against the limit: raw Embree, our backends and whole surveys on the same "
        "rays, with build times and peak memory (see README, Performance)");
    cmd->add_option("surveys", opts->surveys,
                    "Survey files (default: the terrestrial, airborne and car examples)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--threads", opts->threads,
                    "Thread counts to measure, e.g. --threads 1 2 (default: 1 and all cores)");
    cmd->add_option("--backend", opts->backends, "Backends to time (default: embree and bvh)");
    cmd->add_option("--repeats", opts->repeats, "Each figure is the best of this many runs")
        ->capture_default_str();
    cmd->add_option("--min-time", opts->min_time_s,
                    "Seconds each trace measurement repeats its batch")
        ->capture_default_str();
    cmd->add_option("--pulses", opts->pulses, "Only the first N pulses of each survey (0 = all)")
        ->capture_default_str();
    cmd->add_option("--output", opts->output, "Also write the report (Markdown) to this file");
    cmd->add_flag("--quiet", opts->quiet, "No progress lines on stderr");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
