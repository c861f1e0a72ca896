// Helpers of the scan pattern types' YAML parsers: a survey's `scanner:` block.
#pragma once

#include <string>
#include <string_view>

#include "text/yaml_checker.hpp"

namespace beamtrace::detail {

/// "scanner.<name>": the key of a scanner setting in error messages.
[[nodiscard]] inline std::string scanner_key(std::string_view name) {
    return "scanner." + std::string(name);
}

/// Reads node `n[name]`, when present, into `out` if it is a positive number.
inline void scanner_positive(YamlChecker& c, const YAML::Node& n, std::string_view name,
                             double& out) {
    const YAML::Node v = n[std::string(name)];
    if (v && c.number(v, scanner_key(name), out) && !(out > 0)) {
        c.error(v, scanner_key(name), "must be positive");
    }
}

/// Reports every problem of `problems` (a config's validate()) under `scanner`.
inline void scanner_problems(YamlChecker& c, const YAML::Node& n,
                             const std::vector<std::string>& problems) {
    for (const auto& p : problems) {
        c.error(n, "scanner", p);
    }
}

}  // namespace beamtrace::detail
