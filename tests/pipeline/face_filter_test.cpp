#include "beamtrace/pipeline/face_filter.hpp"

#include <gtest/gtest.h>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

TEST(FaceFilter, ParsesSinglesAndRanges) {
    const auto r = parse_face_ranges("5804-5805,12,0-0");
    ASSERT_EQ(r.size(), 3u);
    EXPECT_EQ(r[0].first, 5804u);
    EXPECT_EQ(r[0].last, 5805u);
    EXPECT_EQ(r[1].first, 12u);
    EXPECT_EQ(r[1].last, 12u);
    EXPECT_TRUE(in_ranges(r, 5805));
    EXPECT_TRUE(in_ranges(r, 0));
    EXPECT_FALSE(in_ranges(r, 5806));
    EXPECT_FALSE(in_ranges(r, 11));
    EXPECT_TRUE(parse_face_ranges("").empty());
}

TEST(FaceFilter, RejectsMalformedRanges) {
    for (const char* bad : {"a", "1-", "-3", "5-2", "1,,2", "1.5", "99999999999"}) {
        EXPECT_THROW((void)parse_face_ranges(bad), ConfigError) << bad;
    }
}

}  // namespace
}  // namespace beamtrace
