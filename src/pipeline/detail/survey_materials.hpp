// The materials a survey's physics uses: the scene's materials, with every library material
// (Material::library) resolved at the physics' wavelength. Patterns and colours are kept.
#pragma once

#include <filesystem>
#include <vector>

#include "beamtrace/physics/material.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/scene/scene.hpp"

namespace beamtrace::detail {

/// One Material per scene material, in order. Throws ConfigError naming `scene_file` and the
/// material for an unknown library name.
[[nodiscard]] std::vector<Material> survey_materials(const Scene& scene,
                                                     const PhysicsConfig& physics,
                                                     const std::filesystem::path& scene_file);

}  // namespace beamtrace::detail
