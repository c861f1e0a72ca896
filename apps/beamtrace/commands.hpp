// Subcommands of the beamtrace CLI: each parses its options into a config struct and makes one
// library call.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

#include "beamtrace/core/communicator.hpp"

namespace beamtrace::cli {

/// Registers `scan`; the returned function runs it after parsing and returns the exit code.
std::function<int()> add_scan_command(CLI::App& app);

/// Registers `info FILE`: prints a LAS file's header summary and VLR list.
std::function<int()> add_info_command(CLI::App& app);

/// Registers `survey FILE.yaml`: runs a survey and writes LAS 1.4 and the trajectory.
/// `world`: the MPI ranks this process is one of (mpi_world.hpp), or null for one process.
std::function<int()> add_survey_command(CLI::App& app, Communicator* world);

/// Registers `view FILES...`: ray-traced images of raw LAS files (see docs/view.md).
std::function<int()> add_view_command(CLI::App& app);
/// Registers `render [SCENE.yaml]`: a shaded image (see docs/render.md).
std::function<int()> add_render_command(CLI::App& app);
/// Registers `bench [SURVEYS...]`: throughput against raw Embree on the surveys' own rays.
std::function<int()> add_bench_command(CLI::App& app);
/// Registers `convert IN OUT`: LAS <-> LAZ by OUT's extension (see docs/convert.md).
std::function<int()> add_convert_command(CLI::App& app);
/// Registers `weather-range`: maximum detection range against fog MOR (see docs/weather.md).
std::function<int()> add_weather_range_command(CLI::App& app);

}  // namespace beamtrace::cli
