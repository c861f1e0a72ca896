// The `physics:` block of survey files (docs/physics.md), shared by the survey parser.
#pragma once

#include <yaml-cpp/yaml.h>

#include "beamtrace/physics/pulse.hpp"
#include "text/yaml_checker.hpp"

namespace beamtrace {
struct SensorDataSheet;  // sensor/mechanism_presets.hpp
}

namespace beamtrace::detail {

/// A scanner preset's data sheet as the physics defaults (before parse_physics_block reads the
/// survey's keys): its divergence and wavelength, where it gives them. nullptr: no change.
void apply_data_sheet(const SensorDataSheet* sheet, PhysicsConfig& out);

/// Reads the `physics` map `n` into `out` (starting from its current values); every problem is
/// reported to `c` as `file:line: physics.key: what`, then the config's validate() problems.
void parse_physics_block(YamlChecker& c, const YAML::Node& n, PhysicsConfig& out);

}  // namespace beamtrace::detail
