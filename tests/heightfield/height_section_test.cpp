#include "beamtrace/heightfield/height_section.hpp"

#include <gtest/gtest.h>

#include "beamtrace/core/error.hpp"
#include "beamtrace/heightfield/color_mode.hpp"
#include "beamtrace/heightfield/section_grid.hpp"

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

}  // namespace
}  // namespace beamtrace
