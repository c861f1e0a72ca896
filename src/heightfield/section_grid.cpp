#include "beamtrace/heightfield/section_grid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

void HeightFieldConfig::validate() const {
    std::string problems;
    if (!(cell_size > 0.0) || !std::isfinite(cell_size)) {
        problems += "cell size " + std::to_string(cell_size) + " is not a positive number; ";
    }
    if (sections < 1 || sections > 64) {
        problems += "sections " + std::to_string(sections) + " is outside 1 to 64; ";
    }
    try {
        layout().validate();
    } catch (const ConfigError& e) {
        problems += std::string(e.what()).substr(std::string("height field: ").size()) + "; ";
    }
    if (height_stacks < 0 || height_stacks > kMaxHeightStacks) {
        problems += "height stacks " + std::to_string(height_stacks) + " is outside 0 to " +
                    std::to_string(kMaxHeightStacks) + "; ";
    }
    if (!(stack_gap >= 0.0) || !std::isfinite(stack_gap)) {
        problems += "stack gap " + std::to_string(stack_gap) + " is not a number >= 0; ";
    }
    if (gap_fill_cells < 0 || gap_fill_cells > 64) {
        problems += "gap fill " + std::to_string(gap_fill_cells) + " cells is outside 0 to 64; ";
    }
    if (problems.empty() && memory_budget_bytes < section_bytes()) {
        problems += "memory budget " + std::to_string(memory_budget_bytes) +
                    " bytes is smaller than one section (" + std::to_string(section_bytes()) +
                    " bytes): lower --levels or --section-cells; ";
    }
    if (!problems.empty()) {
        problems.resize(problems.size() - 2);
        throw ConfigError("height field: " + problems);
    }
}

SectionGrid::SectionGrid(const HeightFieldConfig& config, const Vec3d& origin)
    : config_(config), layout_(config.layout()), origin_(origin), n_(config.sections) {
    config_.validate();
    shift_ = layout_.finest_shift();
    window_cells_ = static_cast<std::int64_t>(n_) << shift_;
    const auto count = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
    slots_.resize(count);
    visible_.assign(count, nullptr);
    admitted_.assign(count, false);
}

Vec3d SectionGrid::window_corner() const {
    const double s = config_.section_size();
    return {origin_.x + static_cast<double>(first_x_) * s,
            origin_.y + static_cast<double>(first_y_) * s, origin_.z};
}

Bounds2 SectionGrid::slot_bounds(int slot) const {
    const double s = config_.section_size();
    const double x0 = origin_.x + static_cast<double>(section_x(slot)) * s;
    const double y0 = origin_.y + static_cast<double>(section_y(slot)) * s;
    return {x0, y0, x0 + s, y0 + s};
}

SectionGrid::Plan SectionGrid::plan(double camera_x, double camera_y, std::span<const Bounds2> data,
                                    std::size_t reserved_bytes) const {
    const double s = config_.section_size();
    const double half = static_cast<double>(n_) / 2.0;
    Plan p;
    p.first_x = static_cast<std::int64_t>(std::floor((camera_x - origin_.x) / s - half + 0.5));
    p.first_y = static_cast<std::int64_t>(std::floor((camera_y - origin_.y) / s - half + 0.5));
    const std::size_t count = slots_.size();
    p.admitted.assign(count, false);

    // Rank the slots that touch the data by distance to the camera.
    struct Candidate {
        double distance;
        int slot;
    };
    std::vector<Candidate> candidates;
    for (int i = 0; i < static_cast<int>(count); ++i) {
        const double x0 = origin_.x + static_cast<double>(p.first_x + i % n_) * s;
        const double y0 = origin_.y + static_cast<double>(p.first_y + i / n_) * s;
        const Bounds2 b = {x0, y0, x0 + s, y0 + s};
        const bool touches = std::any_of(data.begin(), data.end(), [&](const Bounds2& d) {
            return d.max_x >= b.min_x && d.min_x < b.max_x && d.max_y >= b.min_y &&
                   d.min_y < b.max_y;
        });
        if (touches) {
            const double dx = std::max({b.min_x - camera_x, 0.0, camera_x - b.max_x});
            const double dy = std::max({b.min_y - camera_y, 0.0, camera_y - b.max_y});
            candidates.push_back({std::hypot(dx, dy), i});
        }
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
        return a.distance != b.distance ? a.distance < b.distance : a.slot < b.slot;
    });
    const std::size_t each = config_.section_bytes();
    const std::uint64_t budget = config_.memory_budget_bytes;
    std::uint64_t used = reserved_bytes;
    for (const Candidate& c : candidates) {
        if (used + each <= budget) {
            used += each;
            p.admitted[static_cast<std::size_t>(c.slot)] = true;
            p.order.push_back(c.slot);
        }
    }
    return p;
}

void SectionGrid::place(const Plan& p) {
    const std::size_t count = slots_.size();
    // Move the sections that stay in the window to their new slots.
    std::vector<std::unique_ptr<HeightSection>> moved(count);
    std::vector<bool> moved_loaded(count, false);
    if (placed_) {
        for (std::size_t i = 0; i < count; ++i) {
            if (!slots_[i]) {
                continue;
            }
            const std::int64_t gx = first_x_ + static_cast<std::int64_t>(i) % n_ - p.first_x;
            const std::int64_t gy = first_y_ + static_cast<std::int64_t>(i) / n_ - p.first_y;
            if (gx >= 0 && gx < n_ && gy >= 0 && gy < n_) {
                const auto j = static_cast<std::size_t>(gy * n_ + gx);
                moved_loaded[j] = visible_[i] != nullptr;
                moved[j] = std::move(slots_[i]);
            }
        }
    }
    // Sections that left the window die with the old array; unadmitted ones are freed here.
    slots_ = std::move(moved);
    for (std::size_t i = 0; i < count; ++i) {
        if (!p.admitted[i]) {
            slots_[i].reset();
            moved_loaded[i] = false;
        }
        visible_[i] = moved_loaded[i] ? slots_[i].get() : nullptr;
    }
    first_x_ = p.first_x;
    first_y_ = p.first_y;
    admitted_ = p.admitted;
    placed_ = true;
    refresh_range();
}

std::vector<int> SectionGrid::recenter(double camera_x, double camera_y,
                                       std::span<const Bounds2> data, std::size_t reserved_bytes) {
    // Free first (place), then allocate: the total never exceeds the budget.
    place(plan(camera_x, camera_y, data, reserved_bytes));
    std::vector<int> fresh;
    for (int i = 0; i < static_cast<int>(slots_.size()); ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (admitted_[k] && !slots_[k]) {
            allocate(i);
            fresh.push_back(i);
        } else if (slots_[k] && visible_[k] == nullptr) {
            fresh.push_back(i);  // allocated but never filled: load again
        }
    }
    return fresh;
}

std::vector<int> SectionGrid::missing_slots() const {
    std::vector<int> out;
    for (int i = 0; i < static_cast<int>(slots_.size()); ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (placed_ && admitted_[k] && !slots_[k]) {
            out.push_back(i);
        }
    }
    return out;
}

void SectionGrid::allocate(int slot) {
    auto& s = slots_[static_cast<std::size_t>(slot)];
    if (!s) {
        s = config_.make_section();
    }
}

bool SectionGrid::adopt(std::int64_t section_x, std::int64_t section_y,
                        std::unique_ptr<HeightSection>& section) {
    const std::int64_t a = section_x - first_x_, b = section_y - first_y_;
    if (!placed_ || !section || a < 0 || b < 0 || a >= n_ || b >= n_) {
        return false;
    }
    const auto k = static_cast<std::size_t>(b * n_ + a);
    if (!admitted_[k] || slots_[k]) {
        return false;
    }
    slots_[k] = std::move(section);
    mark_loaded(static_cast<int>(k));
    return true;
}

bool SectionGrid::holds(std::int64_t section_x, std::int64_t section_y) const {
    const std::int64_t a = section_x - first_x_, b = section_y - first_y_;
    return placed_ && a >= 0 && b >= 0 && a < n_ && b < n_ &&
           slots_[static_cast<std::size_t>(b * n_ + a)] != nullptr;
}

void SectionGrid::mark_loaded(int slot) {
    const auto i = static_cast<std::size_t>(slot);
    if (!slots_[i]) {
        return;
    }
    visible_[i] = slots_[i].get();
    refresh_range();
}

void SectionGrid::refresh_range() {
    max_height_ = kEmptyHeight;
    min_height_ = kEmptyHeight;
    float lo = std::numeric_limits<float>::infinity();
    for (const HeightSection* s : visible_) {
        if (s != nullptr && s->max_height() != kEmptyHeight) {
            max_height_ = std::max(max_height_, s->max_height());
            lo = std::min(lo, s->min_height());
        }
    }
    if (max_height_ != kEmptyHeight) {
        min_height_ = lo;
    }
}

std::size_t SectionGrid::resident_bytes() const {
    std::size_t total = 0;
    for (const auto& s : slots_) {
        total += s ? s->bytes() : 0;
    }
    return total;
}

int SectionGrid::resident_sections() const {
    return static_cast<int>(
        std::count_if(slots_.begin(), slots_.end(), [](const auto& s) { return s != nullptr; }));
}

int SectionGrid::loaded_sections() const {
    return static_cast<int>(std::count_if(visible_.begin(), visible_.end(),
                                          [](const auto* s) { return s != nullptr; }));
}

}  // namespace beamtrace
