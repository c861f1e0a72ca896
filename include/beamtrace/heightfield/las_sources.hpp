// The LAS files behind a view: listed, opened and validated once before any point is read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/heightfield/section_grid.hpp"
#include "beamtrace/io/las.hpp"

namespace beamtrace {

struct LasSource {
    std::filesystem::path path;
    LasHeader header;
    bool compressed = false;  ///< LAZ: read through LasReader
};

/// Every input is a LAS or LAZ file or a directory (its `*.las` and `*.laz` files, sorted by
/// name, not recursive).
/// Each header is parsed and validated by LasReader, so a broken, truncated or compressed file
/// throws InputError naming it before any work starts. Files with no points are kept (they add
/// nothing) and noted in warnings().
class LasSourceSet {
  public:
    explicit LasSourceSet(std::span<const std::filesystem::path> inputs);

    [[nodiscard]] const std::vector<LasSource>& files() const { return files_; }
    [[nodiscard]] std::uint64_t point_count() const { return point_count_; }
    /// Header xy bounds of the files that have points.
    [[nodiscard]] const std::vector<Bounds2>& bounds() const { return bounds_; }
    /// Header bounds over the files with points (both zero when there are none).
    [[nodiscard]] const Vec3d& min() const { return min_; }
    [[nodiscard]] const Vec3d& max() const { return max_; }
    [[nodiscard]] const std::vector<std::string>& warnings() const { return warnings_; }

  private:
    void add_file(const std::filesystem::path& path);

    std::vector<LasSource> files_;
    std::vector<Bounds2> bounds_;
    std::uint64_t point_count_ = 0;
    Vec3d min_, max_;
    std::vector<std::string> warnings_;
};

/// The finest cell edge that suits the files' point density (the `view` default, cell_size 0):
/// kAutoCellSpacings mean point spacings, sqrt(footprint / points) with the footprint the sum
/// of the files' header xy areas, rounded up to a 1-2-5 step (0.1, 0.2, 0.5, 1, 2, ...), so that
/// nearly every cell of a surface holds a point. 1 when the files hold no points or no area.
inline constexpr double kAutoCellSpacings = 1.5;
[[nodiscard]] double auto_cell_size(const LasSourceSet& sources);

/// With an automatic cell size: the fewest quadtree levels (at most field.levels) whose sections
/// are at least twice the files' extent, so that the window around a camera near the data
/// holds all of it. Small files get small sections (less memory, less empty space); large ones
/// keep field.levels.
[[nodiscard]] int auto_levels(const LasSourceSet& sources, const HeightFieldConfig& field);

}  // namespace beamtrace
