// One streaming pass over the LAS files that fills every section waiting to be loaded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/heightfield/las_sources.hpp"
#include "beamtrace/heightfield/section_grid.hpp"

namespace beamtrace {

class ThreadPool;

struct IngestConfig {
    /// Bytes of raw point records read per pread (the loader's only large buffer; it counts
    /// against the memory budget).
    std::size_t block_bytes = std::size_t{4} << 20;
};

struct IngestStats {
    std::uint64_t points_read = 0;
    std::uint64_t points_inserted = 0;  ///< points that landed in a section being loaded
    /// Points outside their file's header bounds (by more than half a scale step): still
    /// inserted where they fall, and reported.
    std::uint64_t points_outside_header = 0;
    double seconds = 0.0;
    std::vector<std::string> warnings;
};

/// Progress callback: (points read so far, points in all files).
using IngestProgress = std::function<void(std::uint64_t, std::uint64_t)>;

/// Reads every file of `sources` once, in order, in blocks, and inserts each point into the
/// section of `slots` (slots of `grid`, allocated and empty, as returned by recenter()) that
/// contains it: finest cell = max height, with the colour attribute of that highest point. Then
/// builds the sections' mipmaps and makes them visible (mark_loaded).
///
/// Decoding is spread over the pool: each pool task scans the whole block and owns the rows of
/// cells with (row / 8) % tasks == task, so no cell is written by two threads and the result
/// does not depend on scheduling. I/O errors throw InputError naming the file.
IngestStats ingest_sections(const LasSourceSet& sources, SectionGrid& grid,
                            std::span<const int> slots, ThreadPool& pool,
                            const IngestConfig& config = {}, const IngestProgress& progress = {});

}  // namespace beamtrace
