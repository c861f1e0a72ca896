#include "beamtrace/core/vec3_text.hpp"

#include <charconv>
#include <cmath>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

Vec3d parse_vec3(std::string_view text, std::string_view what) {
    const auto fail = [&] {
        return ConfigError(std::string(what) + " expects three comma-separated numbers, got '" +
                           std::string(text) + "'");
    };
    double v[3] = {0, 0, 0};
    std::string_view rest = text;
    for (int k = 0; k < 3; ++k) {
        const std::size_t comma = rest.find(',');
        if ((k < 2) != (comma != std::string_view::npos)) {
            throw fail();
        }
        std::string_view item = rest.substr(0, comma);
        while (!item.empty() && item.front() == ' ') {
            item.remove_prefix(1);
        }
        while (!item.empty() && item.back() == ' ') {
            item.remove_suffix(1);
        }
        const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), v[k]);
        if (item.empty() || ec != std::errc() || end != item.data() + item.size() ||
            !std::isfinite(v[k])) {
            throw fail();
        }
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    }
    return {v[0], v[1], v[2]};
}

}  // namespace beamtrace
