// Quoting a user's value in an error message: at most kQuoteMaxChars of it, on one line.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace beamtrace::detail {

/// How much of a user's value an error message quotes (docs/scene-file.md, docs/survey.md).
inline constexpr std::size_t kQuoteMaxChars = 80;

/// `value` cut to at most `max_chars` bytes (at a UTF-8 character boundary) with "..." after
/// a cut, control characters written as \n, \t, \xNN so that the message stays one line.
[[nodiscard]] std::string clip_value(std::string_view value,
                                     std::size_t max_chars = kQuoteMaxChars);

/// clip_value in single quotes: `'value'`.
[[nodiscard]] std::string quote_value(std::string_view value,
                                      std::size_t max_chars = kQuoteMaxChars);

}  // namespace beamtrace::detail
