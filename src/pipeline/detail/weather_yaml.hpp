// The `weather:` block of survey files (docs/weather.md), shared by the survey parser.
#pragma once

#include <yaml-cpp/yaml.h>

#include "beamtrace/physics/weather.hpp"
#include "text/yaml_checker.hpp"

namespace beamtrace::detail {

/// Reads the `weather` map `n` into `out`; every problem is reported to `c` as
/// `file:line: weather.key: what`, then the config's validate() problems.
void parse_weather_block(YamlChecker& c, const YAML::Node& n, WeatherConfig& out);

}  // namespace beamtrace::detail
