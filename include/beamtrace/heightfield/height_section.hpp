// One section of the out-of-core height field: a square quadtree maximum mipmap of heights (Dick,
// Krueger & Westermann 2009) plus one attribute per finest cell from which its colour is made.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "beamtrace/heightfield/huge_page_allocator.hpp"

namespace beamtrace {

/// Height of a cell that holds no point: rays pass through it (it is not "height zero").
inline constexpr float kEmptyHeight = -std::numeric_limits<float>::infinity();

/// Most quadtree levels a section may have.
inline constexpr int kMaxSectionLevels = 16;

/// Most occupied height intervals per finest cell (height stacks).
inline constexpr int kMaxHeightStacks = 8;

/// The shape shared by every section of a grid. Level 0 is the finest; level `levels - 1` the
/// coarsest, with `coarse_cells` x `coarse_cells` cells (the thesis's "32x32 grid with 8 levels"
/// is coarse_cells = 32, levels = 8: 4096 x 4096 finest cells).
struct SectionLayout {
    int coarse_cells = 32;  ///< cells per side at the coarsest level; a power of two
    int levels = 8;         ///< quadtree levels, 1 to kMaxSectionLevels

    /// Throws ConfigError listing every problem (not a power of two, too many cells, ...).
    void validate() const;
    [[nodiscard]] int finest_cells() const { return coarse_cells << (levels - 1); }
    /// log2(finest_cells()).
    [[nodiscard]] int finest_shift() const;
    /// Cells per side at `level`.
    [[nodiscard]] int cells(int level) const { return finest_cells() >> level; }
    /// Index of the first height of `level` in the section's height array.
    [[nodiscard]] std::size_t level_offset(int level) const;
    /// Heights of all levels together.
    [[nodiscard]] std::size_t height_count() const { return level_offset(levels); }
};

/// A section's heights (all levels, one float array, finest level first, rows of increasing y)
/// and, when colours come from the points, one 32-bit attribute per finest cell (see
/// color_mode.hpp for its encoding). Heights are relative to the grid's origin z.
///
/// With height stacks (stacks >= 2), each finest cell also keeps up to `stacks` occupied height
/// intervals [lo, hi] (ascending; points closer than `stack_gap` to an interval join it; when
/// a new interval would make one too many, the two closest neighbours merge), so rays can pass
/// under bridges, power lines and tree crowns. The lowest interval reaches down forever when
/// rays test it (the ground stays solid); the heights (max mipmap) still guide the traversal.
class HeightSection {
  public:
    /// Allocates an all-empty section.
    HeightSection(const SectionLayout& layout, bool with_attributes, int stacks = 0,
                  float stack_gap = 0.0f);

    [[nodiscard]] const SectionLayout& layout() const { return layout_; }
    /// Bytes this section holds (heights, attributes, stacks).
    [[nodiscard]] std::size_t bytes() const;
    /// Bytes a section of this layout holds, before allocating it.
    [[nodiscard]] static std::size_t bytes_for(const SectionLayout& layout, bool with_attributes,
                                               int stacks = 0);

    /// Raises the finest cell (x, y) to `z` when z is higher, taking `attribute` with it. Ties
    /// keep the first point, so a fixed insertion order gives a fixed result.
    void insert(int x, int y, float z, std::uint32_t attribute) {
        const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(finest_) +
                              static_cast<std::size_t>(x);
        if (z > heights_[i]) {
            heights_[i] = z;
            if (!attributes_.empty()) {
                attributes_[i] = attribute;
            }
        }
        if (stacks_ > 1) {
            insert_stack(stack_data_.data() + i * 2 * static_cast<std::size_t>(stacks_), z);
        }
    }

    /// Intervals per cell (0 or 1: no stacks) and the gap that separates them.
    [[nodiscard]] int stacks() const { return stacks_; }
    [[nodiscard]] float stack_gap() const { return stack_gap_; }
    /// The 2 * stacks() floats (lo, hi pairs, ascending; unused pairs are (+inf, -inf)) of
    /// finest cell (x, y); nullptr without stacks.
    [[nodiscard]] const float* stack(int x, int y) const {
        return stacks_ > 1 ? stack_data_.data() +
                                 (static_cast<std::size_t>(y) * static_cast<std::size_t>(finest_) +
                                  static_cast<std::size_t>(x)) *
                                     2 * static_cast<std::size_t>(stacks_)
                           : nullptr;
    }
    /// All stacks, finest cells in row order (empty without stacks).
    [[nodiscard]] std::span<const float> stack_data() const { return stack_data_; }

    /// Recomputes levels 1.. from level 0 (each cell is the max of its four children) and the
    /// lowest height.
    void build_mipmap();

    [[nodiscard]] float height(int level, int x, int y) const {
        return heights_[offsets_[static_cast<std::size_t>(level)] +
                        static_cast<std::size_t>(y) * static_cast<std::size_t>(finest_ >> level) +
                        static_cast<std::size_t>(x)];
    }
    [[nodiscard]] std::uint32_t attribute(int x, int y) const {
        return attributes_.empty()
                   ? 0u
                   : attributes_[static_cast<std::size_t>(y) * static_cast<std::size_t>(finest_) +
                                 static_cast<std::size_t>(x)];
    }
    [[nodiscard]] std::span<const float> heights() const { return heights_; }
    [[nodiscard]] bool has_attributes() const { return !attributes_.empty(); }

    /// Highest (from the coarsest level: call build_mipmap() first) and lowest non-empty finest
    /// height (with stacks: the lowest top of a cell's lowest interval, where rays stop going
    /// down); kEmptyHeight and +inf when the section is empty.
    [[nodiscard]] float max_height() const;
    [[nodiscard]] float min_height() const { return min_height_; }
    /// Finest cells holding at least one point.
    [[nodiscard]] std::size_t occupied_cells() const;

  private:
    void insert_stack(float* intervals, float z) const;

    SectionLayout layout_;
    int finest_ = 0;
    std::array<std::size_t, kMaxSectionLevels + 1> offsets_{};
    // On huge pages where the system allows (huge_page_allocator.hpp): rays' walks and the
    // shading read them all over.
    std::vector<float, HugePageAllocator<float>> heights_;
    std::vector<std::uint32_t, HugePageAllocator<std::uint32_t>> attributes_;
    int stacks_ = 0;
    float stack_gap_ = 0.0f;
    std::vector<float, HugePageAllocator<float>> stack_data_;
    float min_height_ = std::numeric_limits<float>::infinity();
};

}  // namespace beamtrace
