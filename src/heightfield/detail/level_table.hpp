// The heights the hierarchical view traversal reads, per frame: one table of addresses for every
// level of every resident section and for a max pyramid over the whole window above them.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "beamtrace/heightfield/section_grid.hpp"

namespace beamtrace::detail {

/// Most levels of the traversal: the sections' levels plus the window pyramid above them.
inline constexpr int kMaxTraceLevels = 48;

/// Heights for the hierarchical traversal, built once per frame. Level l <= section_top() of
/// window slot s is at address(l * slots + s) (nullptr when the section is not loaded), rows of
/// 2^(finest_shift - l) cells, so a lookup is one table read and one height read. Above the
/// sections' coarsest level a max pyramid over the whole window up to a single cell lets rays
/// skip empty sections and empty parts of the window a few cells at a time; its level
/// section_top() + 1 + k is at address(pyramid_slot(k)), rows of 2^row_shift(k) cells (padded to
/// a power of two, so that every level is addressed alike). Pyramid cells are maxima of their
/// children like the sections' levels, so the traversal stops in the same finest cell as
/// without them.
class LevelTable {
  public:
    explicit LevelTable(const SectionGrid& grid)
        : n_(grid.sections_per_side()),
          top_(grid.layout().levels - 1),
          shift_(grid.layout().finest_shift()) {
        const SectionLayout& layout = grid.layout();
        const auto slots = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
        stacks_ = grid.config().stacks();
        stack_base_.assign(slots, nullptr);
        std::vector<const float*> base(static_cast<std::size_t>(top_ + 1) * slots, nullptr);
        for (std::size_t i = 0; i < slots; ++i) {
            const HeightSection* s = grid.loaded(static_cast<int>(i));
            if (s == nullptr) {
                continue;
            }
            if (stacks_ > 0) {
                stack_base_[i] = s->stack_data().data();
            }
            for (int l = 0; l <= top_; ++l) {
                base[static_cast<std::size_t>(l) * slots + i] =
                    s->heights().data() + layout.level_offset(l);
            }
        }
        for (int l = 0; l <= top_; ++l) {
            cells_[static_cast<std::size_t>(l)] = grid.window_cells() >> l;
        }
        // The pyramid: level top_ + 1 + k has ceil(cells(top_) / 2^(k+1)) cells per side, in
        // rows of 2^row_shift(k) (the next power of two). Sizes first, so that the addresses
        // stay put while it is filled level by level with height().
        std::vector<std::size_t> offsets;
        std::size_t size = 0;
        std::int64_t below = cells_[static_cast<std::size_t>(top_)];
        root_ = top_;
        while (below > 1 && root_ + 1 < kMaxTraceLevels) {
            const std::int64_t c = (below + 1) / 2;
            int lp = 0;
            while ((std::int64_t{1} << lp) < c) {
                ++lp;
            }
            row_shift_[static_cast<std::size_t>(root_ - top_)] = lp;
            offsets.push_back(size);
            size += std::size_t{1} << (2 * lp);
            ++root_;
            cells_[static_cast<std::size_t>(root_)] = c;
            below = c;
        }
        pyramid_.assign(size, kEmptyHeight);
        address_ = std::move(base);
        for (const std::size_t off : offsets) {
            address_.push_back(pyramid_.data() + off);
        }
        for (int l = top_; l < root_; ++l) {
            const auto k = static_cast<std::size_t>(l - top_);
            const int lp = row_shift_[k];
            for (std::int64_t y = 0; y < cells(l); ++y) {
                for (std::int64_t x = 0; x < cells(l); ++x) {
                    float& v = pyramid_[offsets[k] +
                                        static_cast<std::size_t>(((y >> 1) << lp) + (x >> 1))];
                    v = std::max(v, height(l, x, y));
                }
            }
        }
    }
    LevelTable(const LevelTable&) = delete;
    LevelTable& operator=(const LevelTable&) = delete;

    /// The coarsest level (one cell, or the sections' top level when the window has one cell).
    [[nodiscard]] int root() const { return root_; }
    /// The sections' coarsest level.
    [[nodiscard]] int section_top() const { return top_; }
    /// log2 of the finest cells per section side.
    [[nodiscard]] int finest_shift() const { return shift_; }
    /// Sections per window side.
    [[nodiscard]] int sections_per_side() const { return n_; }
    /// Cells per side at `level` (the pyramid's last cells may reach beyond the window).
    [[nodiscard]] std::int64_t cells(int level) const {
        return cells_[static_cast<std::size_t>(level)];
    }
    /// cells(level) for every level (kMaxTraceLevels entries).
    [[nodiscard]] const std::int64_t* cells_table() const { return cells_.data(); }
    /// Entry of address_table() that holds pyramid level section_top() + 1 + k.
    [[nodiscard]] std::size_t pyramid_slot(int k) const {
        return static_cast<std::size_t>(top_ + 1) * static_cast<std::size_t>(n_) *
                   static_cast<std::size_t>(n_) +
               static_cast<std::size_t>(k);
    }
    /// log2 of the row length of pyramid level section_top() + 1 + k.
    [[nodiscard]] int row_shift(int k) const { return row_shift_[static_cast<std::size_t>(k)]; }
    /// The addresses of the levels: sections' levels by level and slot, then the pyramid's.
    [[nodiscard]] const float* const* address_table() const { return address_.data(); }

    [[nodiscard]] float height(int level, std::int64_t x, std::int64_t y) const {
        if (level > top_) {
            const int k = level - top_ - 1;
            return address_[pyramid_slot(k)][static_cast<std::size_t>((y << row_shift(k)) + x)];
        }
        const int sh = shift_ - level;
        const float* b = address_[static_cast<std::size_t>(level) * static_cast<std::size_t>(n_) *
                                      static_cast<std::size_t>(n_) +
                                  static_cast<std::size_t>((y >> sh) * n_ + (x >> sh))];
        if (b == nullptr) {
            return kEmptyHeight;
        }
        const std::int64_t mask = (std::int64_t{1} << sh) - 1;
        return b[static_cast<std::size_t>(((y & mask) << sh) + (x & mask))];
    }

    /// The finest heights of the four neighbours of finest cell (x, y) of a loaded section, in
    /// out: (x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1); kEmptyHeight for those outside the
    /// window or in sections not loaded. Those in the cell's own section (all but those of its
    /// border cells) are read next to it, without a lookup of their section each.
    void finest_neighbours(std::int64_t x, std::int64_t y, float* out) const {
        const std::int64_t mask = (std::int64_t{1} << shift_) - 1;
        const std::int64_t ix = x & mask, iy = y & mask;
        const float* base = address_[static_cast<std::size_t>((y >> shift_) * n_ + (x >> shift_))];
        if (base != nullptr && ix > 0 && ix < mask && iy > 0 && iy < mask) {
            const float* b = base + ((iy << shift_) + ix);
            const std::ptrdiff_t row = std::ptrdiff_t{1} << shift_;
            out[0] = b[1];
            out[1] = b[-1];
            out[2] = b[row];
            out[3] = b[-row];
            return;
        }
        const std::int64_t last = cells(0) - 1;
        const auto at = [&](std::int64_t cx, std::int64_t cy) {
            return cx < 0 || cy < 0 || cx > last || cy > last ? kEmptyHeight : height(0, cx, cy);
        };
        out[0] = at(x + 1, y);
        out[1] = at(x - 1, y);
        out[2] = at(x, y + 1);
        out[3] = at(x, y - 1);
    }

    /// Intervals per finest cell (0: no stacks).
    [[nodiscard]] int stacks() const { return stacks_; }
    /// The stack of finest cell (x, y) of a loaded section.
    [[nodiscard]] const float* stack(std::int64_t x, std::int64_t y) const {
        const float* b = stack_base_[static_cast<std::size_t>((y >> shift_) * n_ + (x >> shift_))];
        const std::int64_t mask = (std::int64_t{1} << shift_) - 1;
        return b + static_cast<std::size_t>((((y & mask) << shift_) + (x & mask)) * 2 * stacks_);
    }

  private:
    int n_;
    int top_;
    int shift_;
    int stacks_ = 0;
    int root_ = 0;
    std::vector<const float*> stack_base_;
    std::vector<const float*> address_;
    std::array<std::int64_t, kMaxTraceLevels> cells_{};
    std::array<int, kMaxTraceLevels> row_shift_{};
    std::vector<float> pyramid_;
};

}  // namespace beamtrace::detail
