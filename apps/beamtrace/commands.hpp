// Subcommands of the beamtrace CLI: each parses its options into a config struct and makes one
// library call.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace beamtrace::cli {

/// Registers `scan`; the returned function runs it after parsing and returns the exit code.
std::function<int()> add_scan_command(CLI::App& app);

}  // namespace beamtrace::cli
