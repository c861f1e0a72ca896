#include "text/text_scan.hpp"

#include <cmath>
#include <limits>

namespace beamtrace::detail {

bool to_float_coordinate(double value, float& out) {
    if (!std::isfinite(value) || std::fabs(value) > std::numeric_limits<float>::max()) {
        return false;
    }
    out = static_cast<float>(value);
    return true;
}

bool iequals(std::string_view a, std::string_view lower_b) {
    if (a.size() != lower_b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        char c = a[i];
        if (c >= 'A' && c <= 'Z') {
            c = static_cast<char>(c - 'A' + 'a');
        }
        if (c != lower_b[i]) {
            return false;
        }
    }
    return true;
}

void TextCursor::skip_space() {
    while (pos_ < text_.size()) {
        const char c = text_[pos_];
        if (c == '\n') {
            ++line_;
        } else if (!is_blank(c)) {
            return;
        }
        ++pos_;
    }
}

std::string_view TextCursor::next() {
    skip_space();
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n' && !is_blank(text_[pos_])) {
        ++pos_;
    }
    return text_.substr(start, pos_ - start);
}

void TextCursor::skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n') {
        ++pos_;
    }
    if (pos_ < text_.size()) {
        ++pos_;
        ++line_;
    }
}

bool TextCursor::at_end() {
    skip_space();
    return pos_ >= text_.size();
}

}  // namespace beamtrace::detail
