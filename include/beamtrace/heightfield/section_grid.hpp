// The N x N window of height-field sections around the camera, and the memory-budget policy
// that decides which of them are resident.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/heightfield/color_mode.hpp"
#include "beamtrace/heightfield/height_section.hpp"

namespace beamtrace {

/// Settings of the height field. Lengths are in the LAS files' units (metres or feet).
struct HeightFieldConfig {
    /// Edge of a finest cell (the thesis found 1.0 right for autzen); 0 (the default): a
    /// ViewSession takes auto_cell_size() of its files (heightfield/las_sources.hpp).
    double cell_size = 0.0;
    int levels = 8;          ///< quadtree levels per section (thesis: 8)
    int section_cells = 32;  ///< cells per side of a section's coarsest level (thesis: 32)
    int sections = 4;        ///< the window holds sections x sections sections (thesis: 4)
    /// Upper bound on the bytes of resident sections plus the loader's read buffers.
    std::uint64_t memory_budget_bytes = 1'000'000'000;  ///< 1 GB, as `view --memory-budget`
    ColorMode color = ColorMode::height;
    /// Height stacks: up to this many occupied height intervals per finest cell (0 or 1: one
    /// column per cell, as in the thesis; 2 to 8: rays pass under bridges and tree crowns).
    int height_stacks = 0;
    /// Points closer than this (vertically) to an interval join it; 0: 3 x cell_size.
    double stack_gap = 0.0;
    /// Runs of at most this many empty finest cells between two occupied ones (in a row or a
    /// column) are closed at the lower of the two heights, so that scan lines and rings of
    /// sparse data read as a surface (heightfield/gap_fill.hpp); 0: none.
    int gap_fill_cells = 2;

    /// Throws ConfigError listing every problem.
    void validate() const;
    [[nodiscard]] SectionLayout layout() const { return {section_cells, levels}; }
    [[nodiscard]] int stacks() const { return height_stacks > 1 ? height_stacks : 0; }
    [[nodiscard]] float stack_gap_or_default() const {
        return static_cast<float>(stack_gap > 0.0 ? stack_gap : 3.0 * cell_size);
    }
    /// Bytes of one section with these settings.
    [[nodiscard]] std::size_t section_bytes() const {
        return HeightSection::bytes_for(layout(), color_mode_has_attribute(color), stacks());
    }
    /// An empty section with these settings.
    [[nodiscard]] std::unique_ptr<HeightSection> make_section() const {
        return std::make_unique<HeightSection>(layout(), color_mode_has_attribute(color), stacks(),
                                               stack_gap_or_default());
    }
    /// World edge length of one section.
    [[nodiscard]] double section_size() const {
        return cell_size * static_cast<double>(layout().finest_cells());
    }
};

/// An axis-aligned rectangle in world xy.
struct Bounds2 {
    double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

/// Sections on a global lattice anchored at `origin` (global section (i, j) covers
/// [origin.x + i s, origin.x + (i + 1) s) x [...] with s = section_size()); the window is the
/// N x N block of them starting at window_first(). Window slot (a, b) is index b * N + a.
///
/// Memory-budget policy (recenter): the sections of the window that touch the input's bounds are
/// ranked by their distance to the camera (nearest first, ties by slot); they are made resident
/// in that order while the total stays within memory_budget_bytes minus the loader's reserved
/// bytes. The others are not resident and render as empty space. Sections that leave the window
/// or fall out of the budget are freed before any new one is allocated, so the budget holds at
/// every moment.
class SectionGrid {
  public:
    /// `origin.z` is the zero of the stored heights.
    SectionGrid(const HeightFieldConfig& config, const Vec3d& origin);

    [[nodiscard]] const HeightFieldConfig& config() const { return config_; }
    [[nodiscard]] const SectionLayout& layout() const { return layout_; }
    [[nodiscard]] const Vec3d& origin() const { return origin_; }
    [[nodiscard]] int sections_per_side() const { return n_; }
    /// Finest cells per side of the whole window.
    [[nodiscard]] std::int64_t window_cells() const { return window_cells_; }
    [[nodiscard]] std::int64_t window_first_x() const { return first_x_; }
    [[nodiscard]] std::int64_t window_first_y() const { return first_y_; }
    /// World position of the window's lower-left corner (z = origin.z).
    [[nodiscard]] Vec3d window_corner() const;

    /// Where the window goes for a camera, and which of its slots the budget policy admits:
    /// a pure function of the camera, the data bounds and the budget (not of what is resident).
    struct Plan {
        std::int64_t first_x = 0, first_y = 0;  ///< global section of window slot 0
        std::vector<bool> admitted;             ///< per window slot
        std::vector<int> order;                 ///< the admitted slots, nearest first
    };
    [[nodiscard]] Plan plan(double camera_x, double camera_y, std::span<const Bounds2> data,
                            std::size_t reserved_bytes) const;

    /// Moves the window to `plan`: sections still in the window and admitted keep their data
    /// (and stay visible when loaded); all others are freed. Allocates nothing.
    void place(const Plan& plan);

    /// Re-centres the window on (camera_x, camera_y) and applies the budget policy (plan() and
    /// place()). Sections still wanted keep their data; new ones are allocated empty and
    /// returned (slots) for the loader to fill; they stay invisible to the renderer until
    /// mark_loaded().
    std::vector<int> recenter(double camera_x, double camera_y, std::span<const Bounds2> data,
                              std::size_t reserved_bytes);

    /// Per window slot, whether the last place() admitted it.
    [[nodiscard]] const std::vector<bool>& admitted() const { return admitted_; }
    /// Admitted slots of the last place() that hold no section.
    [[nodiscard]] std::vector<int> missing_slots() const;
    /// Allocates an empty section in a slot that holds none (for the loader to fill).
    void allocate(int slot);
    /// Installs a loaded section (mipmap built) of global section (section_x, section_y) when
    /// that section lies in the window, its slot is admitted and holds none; then it is visible.
    /// Takes `section` only then (returns true); otherwise leaves it to the caller.
    bool adopt(std::int64_t section_x, std::int64_t section_y,
               std::unique_ptr<HeightSection>& section);
    /// Global section index (x, y) of a window slot.
    [[nodiscard]] std::int64_t section_x(int slot) const { return first_x_ + slot % n_; }
    [[nodiscard]] std::int64_t section_y(int slot) const { return first_y_ + slot / n_; }
    /// Whether global section (x, y) is resident (loaded or being filled).
    [[nodiscard]] bool holds(std::int64_t section_x, std::int64_t section_y) const;

    /// The section in `slot`, loaded or not (nullptr when not resident).
    [[nodiscard]] HeightSection* slot(int slot) {
        return slots_[static_cast<std::size_t>(slot)].get();
    }
    [[nodiscard]] const HeightSection* slot(int slot) const {
        return slots_[static_cast<std::size_t>(slot)].get();
    }
    /// The section in `slot` when it is loaded (visible to the renderer), else nullptr.
    [[nodiscard]] const HeightSection* loaded(int slot) const {
        return visible_[static_cast<std::size_t>(slot)];
    }
    /// Makes a filled section visible (call its build_mipmap() first) and updates the height
    /// range.
    void mark_loaded(int slot);
    /// Bounds of a slot's section in world xy.
    [[nodiscard]] Bounds2 slot_bounds(int slot) const;

    /// Bytes of all allocated sections (loaded or not).
    [[nodiscard]] std::size_t resident_bytes() const;
    [[nodiscard]] int resident_sections() const;
    [[nodiscard]] int loaded_sections() const;

    /// Height of cell (x, y) of `level`, in window cells of that level (0 <= x, y <
    /// window_cells() >> level); kEmptyHeight in sections that are not loaded.
    [[nodiscard]] float height(int level, std::int64_t x, std::int64_t y) const {
        const int shift = shift_ - level;
        const HeightSection* s =
            visible_[static_cast<std::size_t>((y >> shift) * n_ + (x >> shift))];
        if (s == nullptr) {
            return kEmptyHeight;
        }
        const std::int64_t mask = (std::int64_t{1} << shift) - 1;
        return s->height(level, static_cast<int>(x & mask), static_cast<int>(y & mask));
    }
    /// The height stack of finest cell (x, y) (see HeightSection::stack); nullptr without stacks
    /// or where no section is loaded.
    [[nodiscard]] const float* stack(std::int64_t x, std::int64_t y) const {
        const HeightSection* s =
            visible_[static_cast<std::size_t>((y >> shift_) * n_ + (x >> shift_))];
        const std::int64_t mask = (std::int64_t{1} << shift_) - 1;
        return s == nullptr ? nullptr
                            : s->stack(static_cast<int>(x & mask), static_cast<int>(y & mask));
    }
    /// Attribute of finest cell (x, y) (0 where none).
    [[nodiscard]] std::uint32_t attribute(std::int64_t x, std::int64_t y) const {
        const HeightSection* s =
            visible_[static_cast<std::size_t>((y >> shift_) * n_ + (x >> shift_))];
        const std::int64_t mask = (std::int64_t{1} << shift_) - 1;
        return s == nullptr ? 0u
                            : s->attribute(static_cast<int>(x & mask), static_cast<int>(y & mask));
    }

    /// Range of the loaded heights (relative to origin.z); max is kEmptyHeight when none.
    [[nodiscard]] float max_height() const { return max_height_; }
    [[nodiscard]] float min_height() const { return min_height_; }
    /// Intensity drawn white in ColorMode::intensity: the highest intensity read so far (set by
    /// the loader; 0 before any point).
    [[nodiscard]] double intensity_full_scale() const { return intensity_full_scale_; }
    void set_intensity_full_scale(double value) { intensity_full_scale_ = value; }

  private:
    void refresh_range();

    HeightFieldConfig config_;
    SectionLayout layout_;
    Vec3d origin_;
    int n_ = 4;
    int shift_ = 0;
    std::int64_t window_cells_ = 0;
    std::int64_t first_x_ = 0, first_y_ = 0;
    bool placed_ = false;
    std::vector<bool> admitted_;
    std::vector<std::unique_ptr<HeightSection>> slots_;
    std::vector<const HeightSection*> visible_;
    float max_height_ = kEmptyHeight;
    float min_height_ = kEmptyHeight;
    double intensity_full_scale_ = 0.0;
};

}  // namespace beamtrace
