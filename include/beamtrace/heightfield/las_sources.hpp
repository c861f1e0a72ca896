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

}  // namespace beamtrace
