// Quoting users' values in error messages (issue 15, finding 8): at most 80 characters.
#include "text/quote.hpp"

#include <gtest/gtest.h>

#include <string>

namespace beamtrace {
namespace {

TEST(QuoteValue, ShortValuesAreQuotedWhole) {
    EXPECT_EQ(detail::quote_value("middle"), "'middle'");
    EXPECT_EQ(detail::quote_value(""), "''");
    EXPECT_EQ(detail::quote_value(std::string(80, 'a')), "'" + std::string(80, 'a') + "'");
}

TEST(QuoteValue, LongValuesAreCutAtEightyCharacters) {
    const std::string big(std::size_t{100} << 20, 'x');
    EXPECT_EQ(detail::quote_value(big), "'" + std::string(80, 'x') + "...'");
    EXPECT_EQ(detail::clip_value(std::string(81, 'y')), std::string(80, 'y') + "...");
    EXPECT_EQ(detail::clip_value("abcdef", 3), "abc...");
}

TEST(QuoteValue, CutsNeverSplitAUtf8Character) {
    // 79 ASCII bytes then a two-byte character straddling the cut: the character is dropped.
    const std::string s = std::string(79, 'a') + "\xc3\xa9" + "zzz";
    EXPECT_EQ(detail::clip_value(s), std::string(79, 'a') + "...");
    const std::string t = std::string(78, 'a') + "\xc3\xa9" + "zzz";
    EXPECT_EQ(detail::clip_value(t), std::string(78, 'a') + "\xc3\xa9...");
}

TEST(QuoteValue, ControlCharactersAreEscapedSoTheMessageStaysOneLine) {
    EXPECT_EQ(detail::quote_value("a\nb\tc\rd"), "'a\\nb\\tc\\rd'");
    EXPECT_EQ(detail::quote_value(std::string("x\0y\x1f\x7f", 5)), "'x\\x00y\\x1f\\x7f'");
}

}  // namespace
}  // namespace beamtrace
