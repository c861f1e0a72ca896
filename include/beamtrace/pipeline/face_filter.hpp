// Sets of face IDs given as ranges, e.g. "--exclude-faces 5804-5805,12".
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace beamtrace {

struct FaceRange {
    std::uint32_t first = 0;  ///< inclusive
    std::uint32_t last = 0;   ///< inclusive
};

/// Parses "A", "A-B" and comma-separated lists of them; throws ConfigError naming the bad item.
[[nodiscard]] std::vector<FaceRange> parse_face_ranges(std::string_view text);

/// True when `face` lies in one of `ranges`.
[[nodiscard]] bool in_ranges(const std::vector<FaceRange>& ranges, std::uint32_t face);

}  // namespace beamtrace
