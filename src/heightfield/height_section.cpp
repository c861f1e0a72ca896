#include "beamtrace/heightfield/height_section.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

void SectionLayout::validate() const {
    std::string problems;
    if (levels < 1 || levels > kMaxSectionLevels) {
        problems += "levels " + std::to_string(levels) + " is outside 1 to " +
                    std::to_string(kMaxSectionLevels) + "; ";
    }
    if (coarse_cells < 1 || !std::has_single_bit(static_cast<unsigned>(coarse_cells))) {
        problems +=
            "section cells " + std::to_string(coarse_cells) + " is not a positive power of two; ";
    }
    if (problems.empty() && static_cast<long long>(coarse_cells) << (levels - 1) > 65536) {
        problems += "section of " + std::to_string(coarse_cells) + " cells with " +
                    std::to_string(levels) + " levels has more than 65536 finest cells per side; ";
    }
    if (!problems.empty()) {
        problems.resize(problems.size() - 2);
        throw ConfigError("height field: " + problems);
    }
}

int SectionLayout::finest_shift() const {
    return std::countr_zero(static_cast<unsigned>(finest_cells()));
}

std::size_t SectionLayout::level_offset(int level) const {
    std::size_t offset = 0;
    for (int l = 0; l < level; ++l) {
        const auto n = static_cast<std::size_t>(cells(l));
        offset += n * n;
    }
    return offset;
}

HeightSection::HeightSection(const SectionLayout& layout, bool with_attributes, int stacks,
                             float stack_gap)
    : layout_(layout), finest_(layout.finest_cells()), stacks_(stacks), stack_gap_(stack_gap) {
    if (stacks < 0 || stacks > kMaxHeightStacks || !(stack_gap >= 0.0f)) {
        throw ConfigError("height field: height stacks " + std::to_string(stacks) +
                          " outside 0 to " + std::to_string(kMaxHeightStacks) + " or gap " +
                          std::to_string(stack_gap) + " negative");
    }
    layout_.validate();
    for (int l = 0; l <= layout_.levels; ++l) {
        offsets_[static_cast<std::size_t>(l)] = layout_.level_offset(l);
    }
    heights_.assign(layout_.height_count(), kEmptyHeight);
    if (with_attributes) {
        const auto n = static_cast<std::size_t>(finest_);
        attributes_.assign(n * n, 0u);
    }
    if (stacks_ > 1) {
        const auto n = static_cast<std::size_t>(finest_);
        stack_data_.resize(n * n * 2 * static_cast<std::size_t>(stacks_));
        for (std::size_t i = 0; i < stack_data_.size(); i += 2) {
            stack_data_[i] = std::numeric_limits<float>::infinity();
            stack_data_[i + 1] = kEmptyHeight;
        }
    }
}

void HeightSection::insert_stack(float* iv, float z) const {
    const int k = stacks_;
    const float gap = stack_gap_;
    int m = 0;
    while (m < k && iv[2 * m] <= iv[2 * m + 1]) {
        ++m;
    }
    // Joins the interval it is within `gap` of (the first, ascending), then merges neighbours
    // that came within `gap`.
    for (int j = 0; j < m; ++j) {
        if (z >= iv[2 * j] - gap && z <= iv[2 * j + 1] + gap) {
            iv[2 * j] = std::min(iv[2 * j], z);
            iv[2 * j + 1] = std::max(iv[2 * j + 1], z);
            int a = j;
            if (a > 0 && iv[2 * a] - iv[2 * a - 1] <= gap) {
                --a;
            }
            int b = j;
            if (b + 1 < m && iv[2 * b + 2] - iv[2 * b + 1] <= gap) {
                ++b;
            }
            if (a != b) {
                iv[2 * a + 1] = iv[2 * b + 1];
                for (int q = b + 1; q < m; ++q) {
                    iv[2 * (q - (b - a))] = iv[2 * q];
                    iv[2 * (q - (b - a)) + 1] = iv[2 * q + 1];
                }
                for (int q = m - (b - a); q < m; ++q) {
                    iv[2 * q] = std::numeric_limits<float>::infinity();
                    iv[2 * q + 1] = kEmptyHeight;
                }
            }
            return;
        }
    }
    // A new interval, in order; one too many: the two closest neighbours merge.
    std::array<float, 2 * (kMaxHeightStacks + 1)> t{};
    int n = 0;
    bool placed = false;
    for (int j = 0; j < m; ++j) {
        if (!placed && z < iv[2 * j]) {
            t[static_cast<std::size_t>(2 * n)] = z;
            t[static_cast<std::size_t>(2 * n + 1)] = z;
            ++n;
            placed = true;
        }
        t[static_cast<std::size_t>(2 * n)] = iv[2 * j];
        t[static_cast<std::size_t>(2 * n + 1)] = iv[2 * j + 1];
        ++n;
    }
    if (!placed) {
        t[static_cast<std::size_t>(2 * n)] = z;
        t[static_cast<std::size_t>(2 * n + 1)] = z;
        ++n;
    }
    if (n > k) {
        int best = 0;
        for (int j = 1; j + 1 < n; ++j) {
            const auto gj =
                t[static_cast<std::size_t>(2 * j + 2)] - t[static_cast<std::size_t>(2 * j + 1)];
            const auto gb = t[static_cast<std::size_t>(2 * best + 2)] -
                            t[static_cast<std::size_t>(2 * best + 1)];
            if (gj < gb) {
                best = j;
            }
        }
        t[static_cast<std::size_t>(2 * best + 1)] = t[static_cast<std::size_t>(2 * best + 3)];
        for (int j = best + 1; j + 1 < n; ++j) {
            t[static_cast<std::size_t>(2 * j)] = t[static_cast<std::size_t>(2 * j + 2)];
            t[static_cast<std::size_t>(2 * j + 1)] = t[static_cast<std::size_t>(2 * j + 3)];
        }
        --n;
    }
    std::copy_n(t.begin(), 2 * n, iv);
}

std::size_t HeightSection::bytes_for(const SectionLayout& layout, bool with_attributes,
                                     int stacks) {
    const auto n = static_cast<std::size_t>(layout.finest_cells());
    return layout.height_count() * sizeof(float) +
           (with_attributes ? n * n * sizeof(std::uint32_t) : 0) +
           (stacks > 1 ? n * n * 2 * static_cast<std::size_t>(stacks) * sizeof(float) : 0) +
           sizeof(HeightSection);
}

std::size_t HeightSection::bytes() const {
    return heights_.capacity() * sizeof(float) + attributes_.capacity() * sizeof(std::uint32_t) +
           stack_data_.capacity() * sizeof(float) + sizeof(HeightSection);
}

void HeightSection::build_mipmap() {
    const auto cells = static_cast<std::size_t>(finest_) * static_cast<std::size_t>(finest_);
    float lo = std::numeric_limits<float>::infinity();
    if (stacks_ > 1) {
        // Rays going down stop at the lowest top of a cell's lowest interval.
        const auto k2 = 2 * static_cast<std::size_t>(stacks_);
        for (std::size_t i = 0; i < cells; ++i) {
            lo = heights_[i] != kEmptyHeight ? std::min(lo, stack_data_[i * k2 + 1]) : lo;
        }
    } else {
        for (std::size_t i = 0; i < cells; ++i) {
            lo = heights_[i] != kEmptyHeight ? std::min(lo, heights_[i]) : lo;
        }
    }
    min_height_ = lo;
    for (int l = 1; l < layout_.levels; ++l) {
        const auto n = static_cast<std::size_t>(layout_.cells(l));
        const float* child = heights_.data() + offsets_[static_cast<std::size_t>(l - 1)];
        float* parent = heights_.data() + offsets_[static_cast<std::size_t>(l)];
        for (std::size_t y = 0; y < n; ++y) {
            const float* row0 = child + (2 * y) * (2 * n);
            const float* row1 = row0 + 2 * n;
            for (std::size_t x = 0; x < n; ++x) {
                parent[y * n + x] = std::max(std::max(row0[2 * x], row0[2 * x + 1]),
                                             std::max(row1[2 * x], row1[2 * x + 1]));
            }
        }
    }
}

float HeightSection::max_height() const {
    const auto first =
        static_cast<std::ptrdiff_t>(offsets_[static_cast<std::size_t>(layout_.levels - 1)]);
    return *std::max_element(heights_.begin() + first, heights_.end());
}

std::size_t HeightSection::occupied_cells() const {
    const auto n = static_cast<std::size_t>(finest_) * static_cast<std::size_t>(finest_);
    return static_cast<std::size_t>(std::count_if(heights_.begin(),
                                                  heights_.begin() + static_cast<std::ptrdiff_t>(n),
                                                  [](float h) { return h != kEmptyHeight; }));
}

}  // namespace beamtrace
