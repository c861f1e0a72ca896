// Statistics of a LAS file's points, in one streaming pass (bounded memory), like
// `pdal info --stats`: counts by classification, return number and number of returns; minimum,
// maximum and mean of x, y, z, intensity and GPS time; point density over the footprint; the CRS.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include "beamtrace/core/progress.hpp"
#include "beamtrace/io/las_crs.hpp"
#include "beamtrace/io/las_reader.hpp"

namespace beamtrace {

/// Minimum, maximum and mean of one field over the points (all 0 when there are none).
struct LasFieldStats {
    double min = 0.0;
    double max = 0.0;
    double mean = 0.0;
};

struct LasStats {
    std::uint64_t points = 0;  ///< points read (the header's point count)
    /// Points by classification value (0-31 for formats 0-5, whose flags are not counted).
    std::array<std::uint64_t, 256> by_classification{};
    /// Points by return number and by number of returns (index = the value, 0-15).
    std::array<std::uint64_t, 16> by_return_number{};
    std::array<std::uint64_t, 16> by_number_of_returns{};
    LasFieldStats x, y, z, intensity;
    std::optional<LasFieldStats> gps_time;  ///< formats with GPS time only
    /// Area of the points' x-y bounding box, (max x - min x) * (max y - min y), in square CRS
    /// units (m^2 for a projected CRS in metres).
    double footprint_area = 0.0;
    /// points / footprint_area; nothing when the area is 0 (no points, or all on a line).
    std::optional<double> density_per_area;
    LasFileCrs crs;  ///< from the header and (E)VLRs (las_crs.hpp)
};

/// Reads every remaining point of `reader` (LasReader::kChunkPoints at a time) and gathers the
/// statistics; means are compensated (Neumaier) sums divided by the count. `progress` (if set) is
/// called after each chunk with (points read, points in the file). Throws what the reader throws.
[[nodiscard]] LasStats compute_las_stats(LasReader& reader, const ProgressFn& progress = {});

/// A file's summary as one JSON object for scripts (`beamtrace info --json`, docs/formats.md):
/// the header facts, the VLRs, the CRS as {source, epsg, name, wkt, warnings} and, with `stats`,
/// its statistics: counts as objects keyed by the value (only values with points), fields as
/// {min, max, mean} (null without points), density null when undefined.
[[nodiscard]] std::string las_info_json(const std::filesystem::path& path, const LasHeader& header,
                                        std::span<const LasVlr> vlrs, const LasFileCrs& crs,
                                        const LasStats* stats, int indent = 2);

}  // namespace beamtrace
