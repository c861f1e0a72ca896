// One streaming pass over the LAS files that fills every section waiting to be loaded.
#pragma once

#include <atomic>
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
    std::uint32_t max_intensity = 0;  ///< highest LAS intensity read (every point of every file)
    int sections_loaded = 0;          ///< sections filled by this call
    int sections_prefetched = 0;      ///< sections a background load had filled (ViewSession)
    bool cancelled = false;  ///< stopped early by the cancel flag: the sections are partial
    std::vector<std::string> warnings;
};

/// Progress callback: (points read so far, points in all files).
using IngestProgress = std::function<void(std::uint64_t, std::uint64_t)>;

/// A section to fill: global section (section_x, section_y) of a grid with the given field
/// settings and origin (section (i, j) covers [origin.x + i s, origin.x + (i + 1) s) x ...).
struct IngestTarget {
    std::int64_t section_x = 0;
    std::int64_t section_y = 0;
    HeightSection* section = nullptr;  ///< allocated and empty
};

/// Reads every file of `sources` once, in order, in blocks, and inserts each point into the
/// target that contains it (finest cell = max height, with the colour attribute of that highest
/// point), then builds the targets' mipmaps. A point's cell is computed from its global cell
/// index (relative to `origin`), so a section's content depends only on the files and on which
/// section it is, not on the window or on the other targets: a section loaded in the background
/// equals the same section loaded later in the foreground. Touches nothing but the targets, so
/// it may run on a background thread (with its own pool) while the grid is rendered. When
/// `cancel` becomes true it stops after the current block (stats.cancelled; the targets are
/// then partial). I/O errors throw InputError naming the file.
IngestStats ingest_into(const LasSourceSet& sources, const HeightFieldConfig& field,
                        const Vec3d& origin, std::span<const IngestTarget> targets,
                        ThreadPool& pool, const IngestConfig& config = {},
                        const IngestProgress& progress = {},
                        const std::atomic<bool>* cancel = nullptr);

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
