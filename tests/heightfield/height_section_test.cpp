#include "beamtrace/heightfield/height_section.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/heightfield/color_mode.hpp"
#include "beamtrace/heightfield/section_grid.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(HeightSection, StartsEmptyAndKeepsTheHighestPointWithItsAttribute) {
    HeightSection s({2, 3}, true);  // 8 x 8 finest cells
    EXPECT_EQ(s.layout().finest_cells(), 8);
    EXPECT_EQ(s.height(0, 3, 4), kEmptyHeight);
    s.insert(3, 4, 1.5f, 7);
    s.insert(3, 4, 1.0f, 8);  // lower: ignored
    s.insert(3, 4, 1.5f, 9);  // tie: the first point stays
    EXPECT_EQ(s.height(0, 3, 4), 1.5f);
    EXPECT_EQ(s.attribute(3, 4), 7u);
    s.insert(3, 4, 2.0f, 10);
    EXPECT_EQ(s.attribute(3, 4), 10u);
    EXPECT_EQ(s.occupied_cells(), 1u);
}

TEST(HeightSection, MipmapLevelsAreTheMaxOfTheirChildren) {
    HeightSection s({2, 3}, false);
    s.insert(0, 0, 1.0f, 0);
    s.insert(1, 1, 3.0f, 0);
    s.insert(7, 7, -2.0f, 0);
    s.build_mipmap();
    EXPECT_EQ(s.height(1, 0, 0), 3.0f);
    EXPECT_EQ(s.height(1, 1, 0), kEmptyHeight);  // no points below: still empty, not zero
    EXPECT_EQ(s.height(1, 3, 3), -2.0f);
    EXPECT_EQ(s.height(2, 0, 0), 3.0f);
    EXPECT_EQ(s.height(2, 1, 1), -2.0f);
    EXPECT_EQ(s.max_height(), 3.0f);
    EXPECT_EQ(s.min_height(), -2.0f);
    EXPECT_FALSE(s.has_attributes());
}

TEST(HeightSection, CountsItsBytes) {
    const SectionLayout layout{4, 4};  // 32 x 32 finest + 16^2 + 8^2 + 4^2
    EXPECT_EQ(layout.height_count(), 32u * 32 + 16 * 16 + 8 * 8 + 4 * 4);
    const HeightSection s(layout, true);
    EXPECT_GE(s.bytes(), layout.height_count() * 4 + 32 * 32 * 4);
    EXPECT_EQ(s.bytes(), HeightSection::bytes_for(layout, true));
}

TEST(HeightSection, RejectsBadLayouts) {
    EXPECT_THROW(SectionLayout({3, 4}).validate(), ConfigError);
    EXPECT_THROW(SectionLayout({4, 0}).validate(), ConfigError);
    EXPECT_THROW(SectionLayout({1024, 8}).validate(), ConfigError);
    HeightFieldConfig c;
    c.cell_size = -1;
    c.sections = 0;
    try {
        c.validate();
        FAIL();
    } catch (const ConfigError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("cell size"), std::string::npos) << m;
        EXPECT_NE(m.find("sections"), std::string::npos) << m;
    }
}

TEST(HeightColor, RampAndModes) {
    EXPECT_EQ(height_ramp(0.0), (Rgb8{0, 0, 255}));
    EXPECT_EQ(height_ramp(0.5), (Rgb8{255, 255, 0}));
    EXPECT_EQ(height_ramp(1.0), (Rgb8{255, 0, 0}));
    EXPECT_EQ(height_ramp(-3.0), height_ramp(0.0));
    EXPECT_EQ(parse_color_mode("classification"), ColorMode::classification);
    EXPECT_THROW(static_cast<void>(parse_color_mode("rainbow")), ConfigError);
    EXPECT_EQ(attribute_color(ColorMode::rgb, pack_rgb8(1, 2, 3), 0), (Rgb8{1, 2, 3}));
    EXPECT_EQ(attribute_color(ColorMode::intensity, 50, 100), (Rgb8{128, 128, 128}));
    EXPECT_EQ(attribute_color(ColorMode::classification, 2, 0), classification_color(2));
}

/// kB of transparent huge pages in the mapping of /proc/self/smaps that holds address `p`
/// (-1: no such mapping).
long huge_page_kb_at(const void* p) {
    const auto a = reinterpret_cast<std::uintptr_t>(p);
    std::ifstream in("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(in, line)) {
        std::uintptr_t lo = 0, hi = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> lo >> dash >> hi && dash == '-') {
            inside = lo <= a && a < hi;
            continue;
        }
        if (inside && line.rfind("AnonHugePages:", 0) == 0) {
            return std::stol(line.substr(14));
        }
    }
    return -1;
}

/// Whether the system gives transparent huge pages to regions that ask (madvise or always).
bool huge_pages_on_request() {
    std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
    std::string modes;
    std::getline(in, modes);
    return modes.find("[always]") != std::string::npos ||
           modes.find("[madvise]") != std::string::npos;
}

TEST(HugePageAllocator, LargeBlocksAreAlignedToHugePagesAndKeepTheirValues) {
    // 4 MiB + 1 float: a huge-page block (rounded up to 6 MiB); 1000 floats: a plain one.
    std::vector<float, HugePageAllocator<float>> big((std::size_t{4} << 20) / 4 + 1);
    std::vector<float, HugePageAllocator<float>> small(1000);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % kHugePageBytes, 0u);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % alignof(float), 0u);
    for (std::size_t i = 0; i < big.size(); ++i) {
        big[i] = static_cast<float>(i);
    }
    for (std::size_t i = 0; i < small.size(); ++i) {
        small[i] = static_cast<float>(i);
    }
    big.push_back(-1.0f);  // grows: a new block, the values copied
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(big.data()) % kHugePageBytes, 0u);
    for (std::size_t i = 0; i + 1 < big.size(); ++i) {
        ASSERT_EQ(big[i], static_cast<float>(i)) << i;
    }
    EXPECT_EQ(big.back(), -1.0f);
    for (std::size_t i = 0; i < small.size(); ++i) {
        ASSERT_EQ(small[i], static_cast<float>(i)) << i;
    }
}

TEST(HugePageAllocator, A4096CellSectionsHeightsLieOnHugePagesWhereTheSystemAllows) {
    if (!huge_pages_on_request()) {
        BEAMTRACE_SKIP_HARDWARE("transparent huge pages are off on this system");
    }
    // The benchmark's 32x32/8 layout: 4096 x 4096 finest cells, 85 MB of heights.
    HeightSection s({32, 8}, true);
    const float* heights = s.heights().data();
    ASSERT_EQ(reinterpret_cast<std::uintptr_t>(heights) % kHugePageBytes, 0u);
    const long kb = huge_page_kb_at(heights);
    ASSERT_GE(kb, 0) << "no mapping holds the heights";
    // Every page of the heights was written (all empty) when the section was made; allow a
    // system short of huge pages most of them small.
    EXPECT_GE(kb, 2048) << "no huge page under the section's heights";
    // The same heights as anywhere: a point and the levels above it.
    s.insert(4095, 17, 3.5f, 1);
    s.build_mipmap();
    for (int l = 0; l < 8; ++l) {
        EXPECT_EQ(s.height(l, 4095 >> l, 17 >> l), 3.5f) << l;
        EXPECT_EQ(s.height(l, 0, 0), kEmptyHeight) << l;
    }
    EXPECT_EQ(s.attribute(4095, 17), 1u);
}

}  // namespace
}  // namespace beamtrace
