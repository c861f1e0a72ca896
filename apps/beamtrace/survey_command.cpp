#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/memory_usage.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/pipeline/survey_distributed.hpp"
#include "commands.hpp"
#include "interrupt.hpp"
#include "progress_bar.hpp"

namespace beamtrace::cli {
namespace {

/// The options bind to SurveyRunConfig's fields (pipeline/survey.hpp, which holds the defaults).
struct SurveyCommand {
    std::string file;
    SurveyRunConfig run;
    bool quiet = false;
    bool progress = false;
    bool allow_empty = false;
    Communicator* world = nullptr;  ///< the MPI ranks (mpi_world.hpp); null: one process
};

/// The test hook of a rank that dies mid-run (tests/apps/mpi_cli_test.cpp):
/// BEAMTRACE_TEST_MPI_ABORT=RANK:PULSES aborts rank RANK once PULSES pulses are done.
void abort_if_asked(const Communicator& world, std::size_t done) {
    const char* hook = std::getenv("BEAMTRACE_TEST_MPI_ABORT");
    if (hook == nullptr) {
        return;
    }
    const std::string text = hook;
    const auto colon = text.find(':');
    if (colon != std::string::npos && std::stoi(text.substr(0, colon)) == world.rank() &&
        done >= std::stoull(text.substr(colon + 1))) {
        std::abort();
    }
}

/// Across MPI ranks: --threads 0 means the cores the rank is bound to; more threads than those
/// share them (a note says how to unbind).
void fit_threads_to_binding(SurveyRunConfig& run, const Communicator& world) {
    const unsigned cores = available_cores();  // mpirun binds each rank to a core or a socket
    if (run.threads == 0) {
        run.threads = cores;
    } else if (run.threads > cores && world.rank() == 0) {
        std::fprintf(stderr,
                     "beamtrace: note: rank 0 is bound to %u core(s) but runs %u threads; start "
                     "the ranks with `mpirun --bind-to none` (or srun --cpus-per-task=%u)\n",
                     cores, run.threads, run.threads);
    }
}

/// run_survey, or run_survey_distributed on the MPI ranks of o.world.
SurveyResult run_either(const SurveySpec& spec, const SurveyCommand& o, const SurveyRunConfig& run,
                        ProgressBar& bar) {
    if (o.world == nullptr) {
        return run_survey(spec, run,
                          [&](std::size_t done, std::size_t total) { bar.update(done, total); });
    }
    return run_survey_distributed(spec, run, *o.world, [&](std::size_t done, std::size_t total) {
        abort_if_asked(*o.world, done);
        bar.update(done, total);
    });
}

/// Exit status of a survey or scan that wrote no point (without --allow-empty).
constexpr int kEmptyResultExit = 3;

int run(const SurveyCommand& o) {
    // Across MPI ranks every rank reads the file; they agree on any error before going on, so
    // a rank that cannot read it never leaves the others waiting.
    SurveySpec spec;
    std::exception_ptr error;
    try {
        spec = load_survey_spec(o.file);
    } catch (...) {
        error = std::current_exception();
        if (o.world == nullptr) {
            throw;
        }
    }
    if (o.world != nullptr) {
        agree_on_error(*o.world, error);
    }
    // Across MPI ranks rank 0 alone shows progress and the summary.
    const bool reports = o.world == nullptr || o.world->rank() == 0;
    ProgressBar bar("surveying", reports && !o.quiet && (o.progress || stderr_is_terminal()));
    SurveyRunConfig run = o.run;
    if (o.world != nullptr) {
        fit_threads_to_binding(run, *o.world);
    }
    run.cancel = &interrupt_token();
    catch_interrupts();
    const SurveyResult r = run_either(spec, o, run, bar);
    bar.finish();
    if (!reports) {
        return r.points == 0 && r.pulses > 0 && !o.allow_empty ? kEmptyResultExit : 0;
    }
    if (!o.quiet) {
        const std::string spheres =
            r.spheres > 0 ? ", " + std::to_string(r.spheres) + " exact spheres" : "";
        std::printf("scene: %zu triangles%s; pulses: %llu; points: %llu\n", r.triangles,
                    spheres.c_str(), static_cast<unsigned long long>(r.pulses),
                    static_cast<unsigned long long>(r.points));
        if (r.weather_points) {
            std::printf("weather: %llu of the points are the medium's (fog, rain or snow)\n",
                        static_cast<unsigned long long>(*r.weather_points));
        }
        if (r.intensity_reference_range_m) {
            std::printf("intensity: reference range %.2f m", *r.intensity_reference_range_m);
            if (r.intensity_reference_auto) {
                if (r.nominal_range_m) {
                    std::printf(" (auto: half the nominal range %.2f m)", *r.nominal_range_m);
                } else {
                    std::printf(" (auto: the pilot hit nothing)");
                }
            }
            std::printf("\n");
        }
        std::printf("time: build %.3f s, survey %.3f s (%.2f M pulses/s, %.2f M points/s)\n",
                    r.build_s, r.survey_s,
                    r.survey_s > 0 ? static_cast<double>(r.pulses) / r.survey_s / 1e6 : 0.0,
                    r.survey_s > 0 ? static_cast<double>(r.points) / r.survey_s / 1e6 : 0.0);
        std::printf("peak memory: %.1f MB resident\n", static_cast<double>(peak_rss_bytes()) / 1e6);
        for (const auto& p : r.outputs) {
            std::printf("wrote %s\n", p.string().c_str());
        }
        for (const auto& note : r.notes) {
            std::printf("%s\n", note.c_str());
        }
    }
    std::fflush(stdout);
    for (const auto& why : r.few_points_reasons) {
        std::fprintf(stderr, "beamtrace: warning: %s\n", why.c_str());
    }
    if (r.points == 0 && r.pulses > 0 && !o.allow_empty) {
        std::fprintf(stderr,
                     "beamtrace: error: %s: the survey gave no points (see above; the outputs "
                     "are written; --allow-empty accepts an empty result)\n",
                     o.file.c_str());
        return kEmptyResultExit;
    }
    return 0;
}

}  // namespace

std::function<int()> add_survey_command(CLI::App& app, Communicator* world) {
    auto opts = std::make_shared<SurveyCommand>();
    opts->world = world;
    SurveyRunConfig& rc = opts->run;
    CLI::App* cmd = app.add_subcommand(
        "survey",
        "Run a survey file: a scanner on a platform in a scene; writes points.las (LAS "
        "1.4) and trajectory.csv");
    cmd->add_option("file", opts->file, "Survey file (YAML, see docs/survey.md)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--output", rc.output_dir, "Output directory")->required();
    cmd->add_flag("--allow-empty", opts->allow_empty,
                  "Exit 0 even when no pulse gives a point (else: the reasons, and exit 3)");
    cmd->add_option("--threads", rc.threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    cmd->add_option("--seed", rc.seed, "Random seed (recorded in the LAS file)")
        ->capture_default_str();
    cmd->add_option_function<std::string>(
           "--backend", [&rc](const std::string& s) { rc.backend = parse_backend_kind(s); },
           backend_choices())
        ->default_str(std::string(to_string(rc.backend)));
    cmd->add_option("--max-pulses", rc.max_pulses,
                    "Run the first N pulses only (0 = all; the same points as the full run's)")
        ->capture_default_str();
    cmd->add_flag("--quiet", opts->quiet, "No progress bar and no summary");
    cmd->add_flag("--progress", opts->progress,
                  "Show the progress bar even when not on a terminal");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
