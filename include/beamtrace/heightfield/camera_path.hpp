// Camera paths for fly-throughs: CSV files with the header `x,y,z,yaw,pitch`, one pose per row
// in beamtrace's camera convention (core/camera_pose.hpp, docs/camera.md).
#pragma once

#include <filesystem>
#include <vector>

#include "beamtrace/core/camera_pose.hpp"

namespace beamtrace {

/// Reads a camera path: the header line `x,y,z,yaw,pitch` (spaces allowed), then one pose per
/// line (blank lines and lines starting with '#' are skipped). Throws InputError with the file
/// and line for a missing file, a wrong header, a bad number or an empty path.
[[nodiscard]] std::vector<CameraPose> read_camera_path(const std::filesystem::path& path);

}  // namespace beamtrace
