// beamtrace: LiDAR simulation and ray tracing. Maps every error to one line and exit code 2.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <functional>
#include <new>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "commands.hpp"
#include "interrupt.hpp"
#include "mpi_world.hpp"

namespace {

/// The command that ran, for an "out of memory" line: argv after the program name, cut to about
/// 80 characters.
std::string command_line(int argc, char** argv) {
    std::string text;
    for (int i = 1; i < argc; ++i) {
        text += (i > 1 ? " " : "") + std::string(argv[i]);
    }
    return text.size() > 80 ? text.substr(0, 77) + "..." : text;
}

/// Parses the command line: -1 to go on, else the exit status (help, version, a bad option,
/// printed only by the process that `reports`).
int parse(CLI::App& app, int argc, char** argv, bool reports) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        if (reports) {
            std::fprintf(stderr, "beamtrace: error: %s (see --help)\n", e.what());
        }
        return 2;
    } catch (const beamtrace::Error& e) {
        // An option's value rejected by the library parser its option is bound to.
        if (reports) {
            std::fprintf(stderr, "beamtrace: error: %s\n", e.what());
        }
        return 2;
    }
    return -1;
}

}  // namespace

int main(int argc, char** argv) {
    // Under mpirun: every rank runs this; rank 0 alone reports (errors are agreed on, so every
    // rank exits with the same status).
    const auto mpi = beamtrace::cli::start_mpi(argc, argv);
    beamtrace::Communicator* world = mpi ? &mpi->comm() : nullptr;
    const bool reports = world == nullptr || world->rank() == 0;
    CLI::App app{"beamtrace " BEAMTRACE_VERSION " - LiDAR simulator and ray tracer", "beamtrace"};
    app.set_version_flag("--version", "beamtrace " BEAMTRACE_VERSION);
    app.require_subcommand(1);
    app.failure_message([](const CLI::App*, const CLI::Error& e) { return std::string(e.what()); });
    const std::vector<std::pair<std::string, std::function<int()>>> commands{
        {"scan", beamtrace::cli::add_scan_command(app)},
        {"info", beamtrace::cli::add_info_command(app)},
        {"survey", beamtrace::cli::add_survey_command(app, world)},
        {"view", beamtrace::cli::add_view_command(app)},
        {"render", beamtrace::cli::add_render_command(app)},
        {"bench", beamtrace::cli::add_bench_command(app)},
        {"convert", beamtrace::cli::add_convert_command(app)},
        {"weather-range", beamtrace::cli::add_weather_range_command(app)}};
    if (const int status = parse(app, argc, argv, reports); status >= 0) {
        return status;
    }
    try {
        if (world != nullptr && world->size() > 1 && !app.got_subcommand("survey")) {
            throw beamtrace::ConfigError(
                "only `beamtrace survey` runs across MPI ranks; run this command without mpirun");
        }
        for (const auto& [name, run] : commands) {
            if (app.got_subcommand(name)) {
                return run();
            }
        }
    } catch (const beamtrace::Interrupted& e) {
        // SIGINT/SIGTERM (interrupt.hpp): the temporaries are gone; 130 or 143.
        if (reports) {
            std::fprintf(stderr, "beamtrace: %s\n", e.what());
        }
        return beamtrace::cli::interrupted_exit_code(e);
    } catch (const beamtrace::Error& e) {
        if (reports) {
            std::fprintf(stderr, "beamtrace: error: %s\n", e.what());
        }
        return 2;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "beamtrace: error: out of memory running '%s'\n",
                     command_line(argc, argv).c_str());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "beamtrace: internal error: %s\n", e.what());
        return 1;
    }
    return 0;
}
