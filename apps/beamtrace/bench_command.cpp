#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "beamtrace/core/atomic_file.hpp"
#include "beamtrace/core/error.hpp"
#include "commands.hpp"
#include "harness/throughput_bench.hpp"
#include "interrupt.hpp"

namespace beamtrace::cli {
namespace {

/// The options bind to ThroughputBenchConfig's fields (pipeline/throughput_bench.hpp, which
/// holds the defaults); the CLI adds the default survey files, the report file and --quiet.
struct BenchCommand {
    ThroughputBenchConfig config;
    std::string output;
    bool quiet = false;
};

/// The surveys `beamtrace bench` runs by default, relative to the repository root: terrestrial
/// (a tripod panorama), airborne (line scanner over the 1.48 M-triangle SRTM DEM) and a
/// 64-beam spinning scanner on a car.
const char* const kDefaultSurveys[] = {"examples/surveys/tripod_panorama.yaml",
                                       "examples/surveys/airborne_srtm.yaml",
                                       "examples/surveys/car_hdl64.yaml"};

int run(BenchCommand& o) {
    ThroughputBenchConfig& c = o.config;
    if (c.surveys.empty()) {
        for (const char* s : kDefaultSurveys) {
            if (!std::filesystem::exists(s)) {
                throw ConfigError(std::string(s) +
                                  ": not found; run `beamtrace bench` from the repository root "
                                  "or name survey files");
            }
            c.surveys.emplace_back(s);
        }
    }
    c.cancel = &interrupt_token();
    catch_interrupts();
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
    auto opts = std::make_shared<BenchCommand>();
    ThroughputBenchConfig& c = opts->config;
    CLI::App* cmd = app.add_subcommand(
        "bench",
        "Throughput against the limit: raw Embree, our backends and whole surveys on the same "
        "rays, with build times and peak memory (see README, Performance)");
    cmd->add_option("surveys", c.surveys,
                    "Survey files (default: the terrestrial, airborne and car examples)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--threads", c.threads,
                    "Thread counts to measure, e.g. --threads 1 2 (default: 1 and all cores)");
    cmd->add_option_function<std::vector<std::string>>(
        "--backend",
        [&c](const std::vector<std::string>& names) {
            for (const auto& b : names) {
                c.backends.push_back(parse_backend_kind(b));
            }
        },
        "Backends to time (default: embree and bvh)");
    cmd->add_option("--repeats", c.repeats, "Each figure is the best of this many runs")
        ->capture_default_str();
    cmd->add_option("--min-time", c.min_time_s, "Seconds each trace measurement repeats its batch")
        ->capture_default_str();
    cmd->add_option("--pulses", c.max_pulses, "Only the first N pulses of each survey (0 = all)")
        ->capture_default_str();
    cmd->add_option("--output", opts->output, "Also write the report (Markdown) to this file");
    cmd->add_flag("--quiet", opts->quiet, "No progress lines on stderr");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
