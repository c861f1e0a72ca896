#include "beamtrace/heightfield/view_session.hpp"

#include "beamtrace/heightfield/view_job.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <utility>

namespace beamtrace {

/// A background load: the sections it fills (owned here until adopted) and its thread.
struct ViewSession::Load {
    std::vector<std::pair<std::int64_t, std::int64_t>> keys;
    std::vector<std::unique_ptr<HeightSection>> sections;
    std::size_t bytes = 0;
    bool ahead = false;  ///< for the window ahead of the camera (update's look-ahead)
    std::atomic<bool> done{false};
    std::atomic<bool> cancel{false};
    std::atomic<std::uint64_t> points_done{0};
    IngestStats stats;
    std::exception_ptr error;
    std::thread thread;
};

ViewSession::ViewSession(std::span<const std::filesystem::path> inputs,
                         const ViewSessionConfig& config)
    : config_(config), sources_(inputs), pool_(config.threads) {
    if (config_.field.cell_size == 0.0) {
        config_.field.cell_size = auto_cell_size(sources_);
        config_.field.levels = auto_levels(sources_, config_.field);
    }
    config_.field.validate();
    grid_ = std::make_unique<SectionGrid>(config_.field, sources_.min());
}

ViewSession::~ViewSession() {
    if (load_) {
        load_->cancel.store(true);
        if (load_->thread.joinable()) {
            load_->thread.join();
        }
    }
}

std::size_t ViewSession::budgeted_bytes() const {
    std::size_t spare = 0;
    for (const Spare& s : spares_) {
        spare += s.section->bytes();
    }
    return grid_->resident_bytes() + spare + (load_ ? load_->bytes : 0) +
           config_.ingest.block_bytes;
}

std::string ViewSession::not_shown_reason() const {
    const SectionGrid& g = *grid_;
    const int n = g.sections_per_side();
    const Vec3d corner = g.window_corner();
    const double span = config_.field.section_size() * n;
    const auto& data = sources_.bounds();
    const bool beyond = std::any_of(data.begin(), data.end(), [&](const Bounds2& b) {
        return b.min_x < corner.x || b.min_y < corner.y || b.max_x >= corner.x + span ||
               b.max_y >= corner.y + span;
    });
    int with_data = 0, admitted = 0;
    for (int slot = 0; slot < n * n; ++slot) {
        const Bounds2 s = g.slot_bounds(slot);
        if (std::any_of(data.begin(), data.end(), [&](const Bounds2& d) {
                return d.max_x >= s.min_x && d.min_x < s.max_x && d.max_y >= s.min_y &&
                       d.min_y < s.max_y;
            })) {
            ++with_data;
            admitted += g.admitted()[static_cast<std::size_t>(slot)] ? 1 : 0;
        }
    }
    std::string why;
    if (beyond) {
        char size[32];
        std::snprintf(size, sizeof size, "%g", config_.field.section_size());
        why = "the files reach beyond the window of " + std::to_string(n) + "x" +
              std::to_string(n) + " sections of " + size +
              " units around the camera (widen it: --sections, --levels, --cell-size)";
    }
    if (admitted < with_data) {
        why += std::string(why.empty() ? "" : "; ") + "the memory budget of " +
               byte_size_text(config_.field.memory_budget_bytes) + " holds " +
               std::to_string(admitted) + " of the " + std::to_string(with_data) +
               " sections with data (--memory-budget)";
    }
    return why;
}

void ViewSession::note_peak() {
    peak_bytes_ = std::max(peak_bytes_, budgeted_bytes());
}

LoadStatus ViewSession::load_status() const {
    LoadStatus s;
    if (load_) {
        s.loading = !load_->done.load(std::memory_order_acquire);
        s.sections = static_cast<int>(load_->keys.size());
        s.points_done = load_->points_done.load(std::memory_order_relaxed);
        s.points_total = sources_.point_count();
    }
    return s;
}

void ViewSession::start_load(std::vector<std::pair<std::int64_t, std::int64_t>> keys) {
    const std::size_t each = config_.field.section_bytes();
    // The budget holds at every moment: resident + spares + loading + the read buffer.
    const std::size_t fixed = budgeted_bytes() - (load_ ? load_->bytes : 0);
    const std::uint64_t budget = config_.field.memory_budget_bytes;
    std::size_t fit = 0;
    while (fit < keys.size() && fixed + (fit + 1) * each <= budget) {
        ++fit;
    }
    keys.resize(fit);
    if (keys.empty()) {
        return;
    }
    auto load = std::make_unique<Load>();
    load->keys = std::move(keys);
    std::vector<IngestTarget> targets;
    for (const auto& [x, y] : load->keys) {
        load->sections.push_back(config_.field.make_section());
        load->bytes += load->sections.back()->bytes();
        targets.push_back({x, y, load->sections.back().get()});
    }
    if (!loader_pool_) {
        loader_pool_ = std::make_unique<ThreadPool>(config_.loader_threads);
    }
    load_ = std::move(load);
    note_peak();
    // The thread touches only its own sections, the (immutable) sources and copies of the
    // settings; the grid is not shared with it.
    Load* l = load_.get();
    load_->thread = std::thread(
        [this, l, targets = std::move(targets), field = config_.field, origin = grid_->origin()] {
            try {
                l->stats = ingest_into(
                    sources_, field, origin, targets, *loader_pool_, config_.ingest,
                    [l](std::uint64_t done, std::uint64_t) {
                        l->points_done.store(done, std::memory_order_relaxed);
                    },
                    &l->cancel);
            } catch (...) {
                l->error = std::current_exception();
            }
            l->done.store(true, std::memory_order_release);
        });
}

std::unique_ptr<ViewSession::Load> ViewSession::join_load(const IngestProgress& progress) {
    if (!load_) {
        return nullptr;
    }
    while (!load_->done.load(std::memory_order_acquire)) {
        if (progress) {
            progress(load_->points_done.load(std::memory_order_relaxed), sources_.point_count());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    load_->thread.join();
    std::unique_ptr<Load> load = std::move(load_);
    if (load->error) {
        std::rethrow_exception(load->error);
    }
    return load;
}

int ViewSession::adopt(Load& load, bool keep_spares) {
    if (load.stats.cancelled) {
        return 0;
    }
    int adopted = 0;
    for (std::size_t i = 0; i < load.keys.size(); ++i) {
        if (grid_->adopt(load.keys[i].first, load.keys[i].second, load.sections[i])) {
            ++adopted;
        } else if (keep_spares && load.sections[i]) {
            spares_.push_back(
                {load.keys[i].first, load.keys[i].second, std::move(load.sections[i])});
        }
    }
    if (load.stats.max_intensity > 0) {
        grid_->set_intensity_full_scale(
            std::max(static_cast<double>(load.stats.max_intensity), grid_->intensity_full_scale()));
    }
    return adopted;  // the sections neither adopted nor kept are freed with `load`
}

int ViewSession::install_spares() {
    int installed = 0;
    for (std::size_t i = 0; i < spares_.size();) {
        if (grid_->adopt(spares_[i].x, spares_[i].y, spares_[i].section)) {
            ++installed;
            spares_.erase(spares_.begin() + static_cast<std::ptrdiff_t>(i));
        } else {
            ++i;
        }
    }
    return installed;
}

void ViewSession::free_spares_for(std::size_t bytes) {
    const auto half = static_cast<std::int64_t>(grid_->sections_per_side() / 2);
    const std::int64_t cx = grid_->window_first_x() + half, cy = grid_->window_first_y() + half;
    const auto distance = [&](const Spare& s) {
        return (s.x - cx) * (s.x - cx) + (s.y - cy) * (s.y - cy);
    };
    std::sort(spares_.begin(), spares_.end(),
              [&](const Spare& a, const Spare& b) { return distance(a) < distance(b); });
    while (!spares_.empty() && budgeted_bytes() + bytes > config_.field.memory_budget_bytes) {
        spares_.pop_back();
    }
}

IngestStats ViewSession::move_to(const Vec3d& camera_position, const IngestProgress& progress) {
    std::unique_ptr<Load> load = join_load(progress);
    grid_->place(grid_->plan(camera_position.x, camera_position.y, sources_.bounds(),
                             config_.ingest.block_bytes));
    const int prefetched = (load ? adopt(*load, false) : 0) + install_spares();
    load.reset();  // free what was not adopted before allocating
    spares_.clear();
    std::vector<int> slots;
    for (int i = 0; i < static_cast<int>(grid_->admitted().size()); ++i) {
        if (grid_->admitted()[static_cast<std::size_t>(i)] && grid_->loaded(i) == nullptr) {
            grid_->allocate(i);
            slots.push_back(i);
        }
    }
    note_peak();
    IngestStats stats = ingest_sections(sources_, *grid_, slots, pool_, config_.ingest, progress);
    stats.sections_prefetched = prefetched;
    return stats;
}

void ViewSession::prefetch(const Vec3d& next_position) {
    if (load_) {
        return;
    }
    const SectionGrid::Plan plan = grid_->plan(next_position.x, next_position.y, sources_.bounds(),
                                               config_.ingest.block_bytes);
    std::vector<std::pair<std::int64_t, std::int64_t>> keys;
    const int n = grid_->sections_per_side();
    for (const int slot : plan.order) {
        const std::int64_t x = plan.first_x + slot % n, y = plan.first_y + slot / n;
        if (!grid_->holds(x, y)) {
            keys.emplace_back(x, y);
        }
    }
    start_load(std::move(keys));
}

bool ViewSession::update(const Vec3d& camera_position, const Vec3d& ahead_position) {
    bool changed = false;
    std::unique_ptr<Load> finished;
    if (load_ && load_->done.load(std::memory_order_acquire)) {
        finished = join_load({});
    }
    const SectionGrid::Plan plan = grid_->plan(camera_position.x, camera_position.y,
                                               sources_.bounds(), config_.ingest.block_bytes);
    if (plan.first_x != grid_->window_first_x() || plan.first_y != grid_->window_first_y() ||
        plan.admitted != grid_->admitted()) {
        grid_->place(plan);
        changed = true;
    }
    if (finished) {
        // Sections the camera has moved away from meanwhile are kept as spares too.
        changed = adopt(*finished, true) > 0 || changed;
        finished.reset();
    }
    changed = install_spares() > 0 || changed;
    std::vector<std::pair<std::int64_t, std::int64_t>> keys;
    for (const int slot : plan.order) {
        if (grid_->slot(slot) == nullptr) {
            keys.emplace_back(grid_->section_x(slot), grid_->section_y(slot));
        }
    }
    if (load_) {
        if (load_->ahead && !keys.empty()) {
            load_->cancel.store(true);  // the camera's own window comes first
        }
        return changed;
    }
    if (!keys.empty()) {
        free_spares_for(keys.size() * config_.field.section_bytes());
        start_load(std::move(keys));
        return changed;
    }
    // Everything the camera's window admits is loaded: load ahead.
    const SectionGrid::Plan next = grid_->plan(ahead_position.x, ahead_position.y,
                                               sources_.bounds(), config_.ingest.block_bytes);
    const int n = grid_->sections_per_side();
    for (const int slot : next.order) {
        const std::int64_t x = next.first_x + slot % n, y = next.first_y + slot / n;
        const bool spare = std::any_of(spares_.begin(), spares_.end(),
                                       [&](const Spare& s) { return s.x == x && s.y == y; });
        if (!grid_->holds(x, y) && !spare) {
            keys.emplace_back(x, y);
        }
    }
    start_load(std::move(keys));
    if (load_) {
        load_->ahead = true;
    }
    return changed;
}

void ViewSession::finish_loading() {
    std::unique_ptr<Load> load = join_load({});
    if (load) {
        adopt(*load, true);
    }
}

}  // namespace beamtrace
