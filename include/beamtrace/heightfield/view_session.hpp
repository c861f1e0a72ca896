// A view of LAS files: the sources, the section window around the camera, a thread pool; one
// call to move the camera (loading what is missing) and one to render.
#pragma once

#include <filesystem>
#include <memory>
#include <span>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/heightfield/las_ingest.hpp"
#include "beamtrace/heightfield/las_sources.hpp"
#include "beamtrace/heightfield/section_grid.hpp"
#include "beamtrace/heightfield/view_renderer.hpp"

namespace beamtrace {

struct ViewSessionConfig {
    HeightFieldConfig field;
    IngestConfig ingest;
    unsigned threads = 0;  ///< 0: every hardware thread
};

class ViewSession {
  public:
    /// Opens and validates every input (InputError names a broken file); ConfigError for bad
    /// settings. The grid's origin is the lower corner of all header bounds.
    ViewSession(std::span<const std::filesystem::path> inputs, const ViewSessionConfig& config);

    [[nodiscard]] const LasSourceSet& sources() const { return sources_; }
    [[nodiscard]] const SectionGrid& grid() const { return *grid_; }
    [[nodiscard]] ThreadPool& pool() { return pool_; }

    /// Re-centres the window on the camera and loads, in one pass over the files, the sections
    /// that became resident. Stats are empty when nothing had to be loaded.
    IngestStats move_to(const Vec3d& camera_position, const IngestProgress& progress = {});

    [[nodiscard]] ViewImage render(const ViewCamera& camera, const RenderOptions& options) {
        return render_view(*grid_, camera, options, pool_);
    }
    /// Renders into `image`, reusing its buffers.
    void render(const ViewCamera& camera, const RenderOptions& options, ViewImage& image) {
        render_view(*grid_, camera, options, pool_, image);
    }

    /// Bytes counted against the budget: resident sections plus the loader's read buffer.
    [[nodiscard]] std::size_t budgeted_bytes() const {
        return grid_->resident_bytes() + config_.ingest.block_bytes;
    }

  private:
    ViewSessionConfig config_;
    LasSourceSet sources_;
    std::unique_ptr<SectionGrid> grid_;
    ThreadPool pool_;
};

}  // namespace beamtrace
