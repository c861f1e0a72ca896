// Vectors written as text on command lines: "x,y,z".
#pragma once

#include <string_view>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// Parses "x,y,z" (three finite numbers, spaces allowed around them); throws ConfigError
/// "<what> expects three comma-separated numbers, got '<text>'" otherwise.
[[nodiscard]] Vec3d parse_vec3(std::string_view text, std::string_view what);

}  // namespace beamtrace
