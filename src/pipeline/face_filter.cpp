#include "beamtrace/pipeline/face_filter.hpp"

#include <charconv>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

std::uint32_t parse_id(std::string_view s, std::string_view item) {
    std::uint32_t v = 0;
    const auto* end = s.data() + s.size();
    const auto [ptr, ec] = std::from_chars(s.data(), end, v);
    if (s.empty() || ec != std::errc() || ptr != end) {
        throw ConfigError("bad face ID range '" + std::string(item) +
                          "' (expected N or N-M with non-negative integers)");
    }
    return v;
}

}  // namespace

std::vector<FaceRange> parse_face_ranges(std::string_view text) {
    std::vector<FaceRange> out;
    while (!text.empty()) {
        const auto comma = text.find(',');
        const std::string_view item = text.substr(0, comma);
        text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
        const auto dash = item.find('-');
        FaceRange r;
        if (dash == std::string_view::npos) {
            r.first = r.last = parse_id(item, item);
        } else {
            r.first = parse_id(item.substr(0, dash), item);
            r.last = parse_id(item.substr(dash + 1), item);
        }
        if (r.last < r.first) {
            throw ConfigError("bad face ID range '" + std::string(item) + "' (end before start)");
        }
        out.push_back(r);
    }
    return out;
}

bool in_ranges(const std::vector<FaceRange>& ranges, std::uint32_t face) {
    for (const auto& r : ranges) {
        if (face >= r.first && face <= r.last) {
            return true;
        }
    }
    return false;
}

}  // namespace beamtrace
