#include "beamtrace/heightfield/height_section.hpp"

#include <algorithm>
#include <bit>
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

HeightSection::HeightSection(const SectionLayout& layout, bool with_attributes)
    : layout_(layout), finest_(layout.finest_cells()) {
    layout_.validate();
    for (int l = 0; l <= layout_.levels; ++l) {
        offsets_[static_cast<std::size_t>(l)] = layout_.level_offset(l);
    }
    heights_.assign(layout_.height_count(), kEmptyHeight);
    if (with_attributes) {
        const auto n = static_cast<std::size_t>(finest_);
        attributes_.assign(n * n, 0u);
    }
}

std::size_t HeightSection::bytes_for(const SectionLayout& layout, bool with_attributes) {
    const auto n = static_cast<std::size_t>(layout.finest_cells());
    return layout.height_count() * sizeof(float) +
           (with_attributes ? n * n * sizeof(std::uint32_t) : 0) + sizeof(HeightSection);
}

std::size_t HeightSection::bytes() const {
    return heights_.capacity() * sizeof(float) + attributes_.capacity() * sizeof(std::uint32_t) +
           sizeof(HeightSection);
}

void HeightSection::build_mipmap() {
    const auto cells = static_cast<std::size_t>(finest_) * static_cast<std::size_t>(finest_);
    float lo = std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < cells; ++i) {
        lo = heights_[i] != kEmptyHeight ? std::min(lo, heights_[i]) : lo;
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
