// Camera paths for fly-throughs: CSV files with the header `x,y,z,yaw,pitch`.
#pragma once

#include <filesystem>
#include <vector>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct CameraPose {
    Vec3d position;
    double yaw_deg = 0.0;
    double pitch_deg = 0.0;
};

/// Reads a camera path: the header line `x,y,z,yaw,pitch` (spaces allowed), then one pose per
/// line (blank lines and lines starting with '#' are skipped). Throws InputError with the file
/// and line for a missing file, a wrong header, a bad number or an empty path.
[[nodiscard]] std::vector<CameraPose> read_camera_path(const std::filesystem::path& path);

/// Parses "x,y,z,yaw,pitch"; throws ConfigError naming `what` otherwise.
[[nodiscard]] CameraPose parse_camera_pose(const std::string& text, const std::string& what);

}  // namespace beamtrace
