// Beam tables of spinning sensors in CSV (docs/sensors.md, "Your own table"): one row per laser
// in firing order, a header naming the columns:
//   elevation_deg[,azimuth_offset_deg][,time_offset_s][,channel]
// elevation_deg is required; the others may be left out (defaults: 0 offset, evenly staggered
// times, channel = row). Lines starting with '#' and blank lines are skipped.
#pragma once

#include <cstddef>
#include <filesystem>

#include "beamtrace/sensor/rotating_scanner.hpp"

namespace beamtrace {

/// The largest beam table file read: 4 MiB.
inline constexpr std::size_t kMaxBeamTableBytes = std::size_t{4} << 20;
/// The most rows a beam table may have (channels are 16-bit).
inline constexpr std::size_t kMaxBeamTableRows = 65536;

/// Replaces the beam rows of `config` (elevations, azimuth offsets, time offsets, channels) with
/// the table in `path`. Throws InputError naming the file, line and column of the first problem.
/// Whether the times fit the firing period is checked by config.validate().
void read_beam_table_csv(const std::filesystem::path& path, RotatingScannerConfig& config);

/// Writes the beam rows of `config` with all four columns, numbers in their shortest exact form
/// (read_beam_table_csv gives back the same values). Throws InputError if it cannot write.
void write_beam_table_csv(const std::filesystem::path& path, const RotatingScannerConfig& config);

}  // namespace beamtrace
