// Counting the nodes of a YAML text before building them: yaml-cpp takes some 500 bytes per
// node, so a few MiB of `[0,0,0],` would take gigabytes as a YAML::Node tree.
#pragma once

#include <cstddef>
#include <string>

namespace beamtrace::detail {

/// The most YAML nodes (scalars, lists, maps, aliases) a scene or survey file may hold
/// (docs/scene-file.md, docs/survey.md): 200 000, some 50 000 waypoints, about 100 MB as nodes.
inline constexpr std::size_t kMaxYamlNodes = 200000;

/// The nodes of `text`, counted by yaml-cpp's event parser (which builds none), stopping at
/// `stop_after` + 1. A syntax error throws the parser's YAML::ParserException.
[[nodiscard]] std::size_t count_yaml_nodes(const std::string& text, std::size_t stop_after);

}  // namespace beamtrace::detail
