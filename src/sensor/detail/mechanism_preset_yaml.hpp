// A mechanism's `preset` key in a survey's `scanner:` block (sensor/mechanism_presets.hpp): the
// preset's config first, then the block's other keys override it.
#pragma once

#include <span>
#include <string>

#include "beamtrace/sensor/mechanism_presets.hpp"
#include "sensor/detail/scanner_yaml.hpp"

namespace beamtrace::detail {

/// When `n` has `preset`, replaces `out` with that preset's config and returns its data sheet;
/// nullptr (after reporting an unknown name) otherwise.
template <class Config>
const SensorDataSheet* parse_mechanism_preset(YamlChecker& c, const YAML::Node& n,
                                              std::span<const MechanismPreset<Config>> presets,
                                              Config& out) {
    const YAML::Node p = n["preset"];
    if (!p) {
        return nullptr;
    }
    const MechanismPreset<Config>* preset =
        find_mechanism_preset(presets, p.IsScalar() ? p.Scalar() : std::string());
    if (preset == nullptr) {
        c.error(p, "scanner.preset",
                "unknown preset (expected " + mechanism_preset_names(presets) + ")");
        return nullptr;
    }
    out = preset->make();
    return &preset->sheet;
}

}  // namespace beamtrace::detail
