#include <gtest/gtest.h>

#include "beamtrace/heightfield/gap_fill.hpp"

namespace beamtrace {
namespace {

HeightSection small_section() {
    return HeightSection({8, 2}, true);
}  // 16 x 16 finest cells

TEST(GapFill, ClosesShortRunsInRowsAtTheLowerHeightWithItsAttribute) {
    HeightSection s = small_section();
    s.insert(5, 3, 5.0f, 11);
    s.insert(8, 3, 2.0f, 22);   // a gap of two cells: filled at 2 with attribute 22
    s.insert(11, 3, 9.0f, 33);  // a gap of two more: filled at 2 again (the lower is cell 8)
    EXPECT_EQ(fill_gaps(s, 2), 4u);
    for (const int x : {6, 7, 9, 10}) {
        EXPECT_EQ(s.height(0, x, 3), 2.0f) << x;
        EXPECT_EQ(s.attribute(x, 3), 22u) << x;
    }
    EXPECT_EQ(s.height(0, 4, 3), kEmptyHeight);  // five cells to the edge: not a gap
    EXPECT_EQ(s.height(0, 5, 2), kEmptyHeight);  // nor are other rows
    EXPECT_EQ(s.height(0, 5, 3), 5.0f);          // occupied cells keep their height
}

TEST(GapFill, LeavesWideGapsAndFillsColumnsToo) {
    HeightSection s = small_section();
    s.insert(4, 4, 1.0f, 1);
    s.insert(8, 4, 1.0f, 1);  // three empty cells between: wider than 2
    s.insert(10, 5, 3.0f, 2);
    s.insert(10, 7, 4.0f, 3);  // one empty cell between them in column 10
    EXPECT_EQ(fill_gaps(s, 2), 1u);
    EXPECT_EQ(s.height(0, 6, 4), kEmptyHeight);
    EXPECT_EQ(s.height(0, 10, 6), 3.0f);
    EXPECT_EQ(s.attribute(10, 6), 2u);
    EXPECT_EQ(fill_gaps(s, 3), 3u);  // now the row's gap of three closes
    EXPECT_EQ(s.height(0, 6, 4), 1.0f);
    EXPECT_EQ(fill_gaps(s, 0), 0u);
}

TEST(GapFill, FilledCellsJoinTheMipmap) {
    HeightSection s = small_section();
    s.insert(4, 5, 7.0f, 0);
    s.insert(6, 5, 8.0f, 0);
    fill_gaps(s, 1);
    s.build_mipmap();
    EXPECT_EQ(s.height(1, 2, 2), 7.0f);  // parent of (4..5, 4..5): (4, 5) and the filled (5, 5)
    EXPECT_EQ(s.occupied_cells(), 3u);
}

TEST(GapFill, RunsToTheSectionsEdgeTakeTheNearestHeight) {
    // Their other end is in the next section: without this every border would be a seam.
    HeightSection s = small_section();
    s.insert(1, 8, 2.0f, 5);   // one cell to the west edge
    s.insert(13, 8, 3.0f, 6);  // two cells to the east edge
    s.insert(8, 2, 4.0f, 7);   // two cells to the south edge
    EXPECT_EQ(fill_gaps(s, 2), 1u + 2u + 2u);
    EXPECT_EQ(s.height(0, 0, 8), 2.0f);
    EXPECT_EQ(s.attribute(0, 8), 5u);
    EXPECT_EQ(s.height(0, 15, 8), 3.0f);
    EXPECT_EQ(s.height(0, 8, 0), 4.0f);
    EXPECT_EQ(s.height(0, 2, 8), kEmptyHeight);  // between 1 and 13: eleven cells, not a gap
    HeightSection far = small_section();
    far.insert(12, 8, 3.0f, 6);  // three cells to the edge: left alone
    EXPECT_EQ(fill_gaps(far, 2), 0u);
}

}  // namespace
}  // namespace beamtrace
