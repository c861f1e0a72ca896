#include <gtest/gtest.h>

#include "beamtrace/heightfield/gap_fill.hpp"

namespace beamtrace {
namespace {

HeightSection small_section() {
    return HeightSection({4, 2}, true);
}  // 8 x 8 finest cells

TEST(GapFill, ClosesShortRunsInRowsAtTheLowerHeightWithItsAttribute) {
    HeightSection s = small_section();
    s.insert(1, 3, 5.0f, 11);
    s.insert(4, 3, 2.0f, 22);  // a gap of two cells: filled at 2 with attribute 22
    s.insert(7, 3, 9.0f, 33);  // a gap of two more: filled at 2 again (the lower is cell 4)
    EXPECT_EQ(fill_gaps(s, 2), 4u);
    for (const int x : {2, 3, 5, 6}) {
        EXPECT_EQ(s.height(0, x, 3), 2.0f) << x;
        EXPECT_EQ(s.attribute(x, 3), 22u) << x;
    }
    EXPECT_EQ(s.height(0, 0, 3), kEmptyHeight);  // the edge is not a gap
    EXPECT_EQ(s.height(0, 1, 2), kEmptyHeight);  // nor are other rows
    EXPECT_EQ(s.height(0, 1, 3), 5.0f);          // occupied cells keep their height
}

TEST(GapFill, LeavesWideGapsAndFillsColumnsToo) {
    HeightSection s = small_section();
    s.insert(0, 0, 1.0f, 1);
    s.insert(4, 0, 1.0f, 1);  // three empty cells between: wider than 2
    s.insert(6, 1, 3.0f, 2);
    s.insert(6, 3, 4.0f, 3);  // one empty cell between them in column 6
    EXPECT_EQ(fill_gaps(s, 2), 1u);
    EXPECT_EQ(s.height(0, 2, 0), kEmptyHeight);
    EXPECT_EQ(s.height(0, 6, 2), 3.0f);
    EXPECT_EQ(s.attribute(6, 2), 2u);
    EXPECT_EQ(fill_gaps(s, 3), 3u);  // now the row's gap of three closes
    EXPECT_EQ(s.height(0, 2, 0), 1.0f);
    EXPECT_EQ(fill_gaps(s, 0), 0u);
}

TEST(GapFill, FilledCellsJoinTheMipmap) {
    HeightSection s = small_section();
    s.insert(0, 5, 7.0f, 0);
    s.insert(2, 5, 8.0f, 0);
    fill_gaps(s, 1);
    s.build_mipmap();
    EXPECT_EQ(s.height(1, 0, 2), 7.0f);  // parent of (0..1, 4..5): the filled (1, 5) and (0, 5)
    EXPECT_EQ(s.occupied_cells(), 3u);
}

}  // namespace
}  // namespace beamtrace
