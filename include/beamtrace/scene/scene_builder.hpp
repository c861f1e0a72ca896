// Turns a scene description into the triangle set the backends trace.
#pragma once

#include <filesystem>

#include "beamtrace/scene/scene.hpp"
#include "beamtrace/scene/scene_spec.hpp"

namespace beamtrace {

/// Loads every part (each file once), triangulates spheres and planes, applies the transforms and
/// concatenates the parts in file order (face IDs follow). Throws InputError for unreadable parts.
/// (Instances are copied for now: a two-level structure that shares their triangles is pending.)
[[nodiscard]] Scene build_scene(const SceneSpec& spec);

/// load_scene_spec + build_scene.
[[nodiscard]] Scene load_scene_file(const std::filesystem::path& path);

}  // namespace beamtrace
