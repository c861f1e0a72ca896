#include "text/quote.hpp"

#include <array>

namespace beamtrace::detail {
namespace {

/// Appends `c`, escaped when it is a control character.
void append_char(std::string& out, unsigned char c) {
    if (c == '\n') {
        out += "\\n";
    } else if (c == '\t') {
        out += "\\t";
    } else if (c == '\r') {
        out += "\\r";
    } else if (c < 0x20 || c == 0x7f) {
        constexpr std::array<char, 16> kHex = {'0', '1', '2', '3', '4', '5', '6', '7',
                                               '8', '9', 'a', 'b', 'c', 'd', 'e', 'f'};
        out += "\\x";
        out += kHex[c >> 4];
        out += kHex[c & 0xf];
    } else {
        out += static_cast<char>(c);
    }
}

}  // namespace

std::string clip_value(std::string_view value, std::size_t max_chars) {
    std::size_t keep = value.size();
    if (keep > max_chars) {
        keep = max_chars;
        // Do not cut a UTF-8 character: back off over continuation bytes (10xxxxxx).
        while (keep > 0 && (static_cast<unsigned char>(value[keep]) & 0xc0) == 0x80) {
            --keep;
        }
    }
    std::string out;
    out.reserve(keep + 3);
    for (std::size_t i = 0; i < keep; ++i) {
        append_char(out, static_cast<unsigned char>(value[i]));
    }
    if (keep < value.size()) {
        out += "...";
    }
    return out;
}

std::string quote_value(std::string_view value, std::size_t max_chars) {
    return "'" + clip_value(value, max_chars) + "'";
}

}  // namespace beamtrace::detail
