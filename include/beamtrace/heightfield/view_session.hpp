// A view of LAS files: the sources, the section window around the camera, a thread pool; one
// call to move the camera (loading what is missing) and one to render; and background loading
// of sections (for the next poses of a path, or for an interactive camera) on a loader thread.
#pragma once

#include <atomic>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/heightfield/las_ingest.hpp"
#include "beamtrace/heightfield/las_sources.hpp"
#include "beamtrace/heightfield/section_grid.hpp"
#include "beamtrace/heightfield/view_renderer.hpp"

namespace beamtrace {

struct ViewSessionConfig {
    HeightFieldConfig field;
    IngestConfig ingest;
    unsigned threads = 0;         ///< 0: every hardware thread
    unsigned loader_threads = 1;  ///< threads of the background loader (0: every hardware thread)
};

/// What the background loader is doing: sections in flight and points read of this pass.
struct LoadStatus {
    bool loading = false;
    int sections = 0;
    std::uint64_t points_done = 0;
    std::uint64_t points_total = 0;
};

class ViewSession {
  public:
    /// Opens and validates every input (InputError names a broken file); ConfigError for bad
    /// settings. The grid's origin is the lower corner of all header bounds.
    ViewSession(std::span<const std::filesystem::path> inputs, const ViewSessionConfig& config);
    /// Stops a background load (cancelled after its current block) and waits for it.
    ~ViewSession();
    ViewSession(const ViewSession&) = delete;
    ViewSession& operator=(const ViewSession&) = delete;

    [[nodiscard]] const LasSourceSet& sources() const { return sources_; }
    [[nodiscard]] const SectionGrid& grid() const { return *grid_; }
    [[nodiscard]] ThreadPool& pool() { return pool_; }

    /// Re-centres the window on the camera and makes every section the budget admits there
    /// resident and loaded: it waits for a background load in flight (reporting its progress),
    /// adopts the sections it loaded, and loads the rest in one pass over the files. The grid
    /// is then exactly what it would be without any background loading (same window, same
    /// sections, same contents), so frames rendered after move_to() do not depend on
    /// prefetch(). Stats are empty when nothing had to be loaded; sections_prefetched counts
    /// the adopted ones.
    IngestStats move_to(const Vec3d& camera_position, const IngestProgress& progress = {});

    /// Starts loading, on the loader thread, the sections the window at `next_position` will
    /// need that are not resident now, nearest first, as many as fit in the memory budget next
    /// to the resident ones (the budget holds at every moment: resident + loading + one read
    /// buffer). Leaves the grid untouched, so the current frame can be rendered meanwhile; the
    /// next move_to(next_position) adopts them. Does nothing while a load is in flight.
    void prefetch(const Vec3d& next_position);

    /// Never waits (for interactive views): adopts the sections of a finished background load,
    /// moves the window to the camera (freeing sections it no longer admits, keeping the
    /// others visible) and, when no load is in flight, starts loading the admitted sections that
    /// are missing. Returns true when the grid changed. Rethrows a background load's error.
    bool update(const Vec3d& camera_position) { return update(camera_position, camera_position); }

    /// The same, looking ahead: once the camera's window has every section it admits, loads
    /// in the background the sections the window at `ahead_position` (where the camera is
    /// heading) will need, as far as the budget leaves room next to the resident ones. They are
    /// kept aside as spares (counted in the budget) and shown as soon as the window reaches
    /// them; spares farthest from the camera are freed first when the camera's own window
    /// needs the room, and a look-ahead load in flight is cancelled then.
    bool update(const Vec3d& camera_position, const Vec3d& ahead_position);

    /// Loaded sections kept aside for the window ahead (see update).
    [[nodiscard]] int spare_sections() const { return static_cast<int>(spares_.size()); }

    /// Waits for a background load in flight and adopts what it loaded.
    void finish_loading();

    [[nodiscard]] LoadStatus load_status() const;

    [[nodiscard]] ViewImage render(const ViewCamera& camera, const RenderOptions& options) {
        return render_view(*grid_, camera, options, pool_);
    }
    /// Renders into `image`, reusing its buffers.
    void render(const ViewCamera& camera, const RenderOptions& options, ViewImage& image) {
        render_view(*grid_, camera, options, pool_, image);
    }

    /// Bytes counted against the budget: resident sections, sections being loaded in the
    /// background, plus the loader's read buffer.
    [[nodiscard]] std::size_t budgeted_bytes() const;
    /// Why points may be missing from the sections in view, for the user: the files reach beyond
    /// the window of sections around the camera, and/or the memory budget holds fewer sections
    /// than the window has with data. Empty when neither holds.
    [[nodiscard]] std::string not_shown_reason() const;
    /// The most budgeted_bytes() seen since construction (sampled whenever sections are
    /// allocated).
    [[nodiscard]] std::size_t peak_budgeted_bytes() const { return peak_bytes_; }

  private:
    struct Load;
    /// Starts a background load of `keys` (global sections).
    void start_load(std::vector<std::pair<std::int64_t, std::int64_t>> keys);
    /// Waits for the load in flight (calling `progress` meanwhile) and takes it.
    std::unique_ptr<Load> join_load(const IngestProgress& progress);
    /// Installs what a finished load filled that the grid admits; keeps the rest as spares
    /// (`keep_spares`) or frees it.
    int adopt(Load& load, bool keep_spares);
    /// Installs the spares the grid now admits; returns how many.
    int install_spares();
    /// Frees spares, farthest from the window's centre first, until `bytes` more fit in the
    /// budget next to the resident sections, the spares left and the read buffer.
    void free_spares_for(std::size_t bytes);

    /// A loaded section outside the window, kept for the window ahead.
    struct Spare {
        std::int64_t x = 0, y = 0;
        std::unique_ptr<HeightSection> section;
    };
    void note_peak();

    ViewSessionConfig config_;
    LasSourceSet sources_;
    std::unique_ptr<SectionGrid> grid_;
    ThreadPool pool_;
    std::unique_ptr<ThreadPool> loader_pool_;
    std::unique_ptr<Load> load_;
    std::vector<Spare> spares_;
    std::size_t peak_bytes_ = 0;
};

}  // namespace beamtrace
