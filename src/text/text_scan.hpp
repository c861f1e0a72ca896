// Number parsing and whitespace tokenising over in-memory text (std::from_chars, no iostreams).
#pragma once

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <system_error>

namespace beamtrace::detail {

/// Blanks inside a line (the line break '\n' is not one).
[[nodiscard]] constexpr bool is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// Parses all of `token` as a number (a leading '+' is allowed); false if malformed or out of
/// range.
template <typename T>
[[nodiscard]] bool parse_number(std::string_view token, T& out) {
    if (!token.empty() && token.front() == '+') {
        token.remove_prefix(1);
        if (!token.empty() && token.front() == '-') {
            return false;
        }
    }
    if (token.empty()) {
        return false;
    }
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, out);
    return ec == std::errc() && ptr == end;
}

/// Converts a coordinate to float; false if it is not finite or does not fit in a float.
[[nodiscard]] bool to_float_coordinate(double value, float& out);

/// ASCII case-insensitive comparison (`b` must be lower case).
[[nodiscard]] bool iequals(std::string_view a, std::string_view lower_b);

/// Whitespace-separated tokens of a text, counting lines for error messages.
class TextCursor {
  public:
    explicit TextCursor(std::string_view text, long first_line = 1)
        : text_(text), line_(first_line) {}

    /// The next token, or an empty view at the end of the text.
    [[nodiscard]] std::string_view next();
    /// Skips the rest of the current line, including its line break.
    void skip_line();
    /// True if only whitespace is left.
    [[nodiscard]] bool at_end();
    /// Line of the current position (that of the last token returned by next()).
    [[nodiscard]] long line() const { return line_; }

  private:
    void skip_space();

    std::string_view text_;
    std::size_t pos_ = 0;
    long line_;
};

}  // namespace beamtrace::detail
