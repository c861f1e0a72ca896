// The survey's physics materials: the scene's materials (with library materials looked up at
// the physics' wavelength), in the order of the scene's material indices.
#pragma once

#include <filesystem>
#include <vector>

#include "beamtrace/physics/material.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/scene/scene.hpp"

namespace beamtrace::detail {

/// Throws ConfigError naming `scene_file` and the material for an unknown library material.
[[nodiscard]] std::vector<Material> survey_materials(const Scene& scene,
                                                     const PhysicsConfig& physics,
                                                     const std::filesystem::path& scene_file);

}  // namespace beamtrace::detail
