// Text forms of render settings shared by the CLI and scripts: lights and image sizes (camera
// poses: core/camera_pose.hpp), and a default view that frames a scene.
#pragma once

#include <string_view>
#include <utility>

#include "beamtrace/core/aabb.hpp"
#include "beamtrace/render/camera.hpp"
#include "beamtrace/render/shading.hpp"

namespace beamtrace {

/// `dir:AZ,EL[,E]`: a directional light from azimuth AZ (degrees, counter-clockwise from +x
/// towards +y) and elevation EL (degrees above the horizontal) with irradiance E (default 1).
/// `point:X,Y,Z[,P]`: a point light at (X, Y, Z) metres with power P (default 1; E = P / r^2).
/// Throws ConfigError naming the text and the problem.
[[nodiscard]] Light parse_light(std::string_view text);

/// `WxH`, e.g. `640x480` -> {640, 480}; throws ConfigError.
[[nodiscard]] std::pair<int, int> parse_image_size(std::string_view text);

/// A view of the whole box from azimuth 225 degrees (from the -x,-y side) and 25 degrees up: the
/// pinhole is set back until the box's bounding sphere fits the vertical field of view; the
/// orthographic view is as wide as that sphere (plus 10 %). Keeps the image size, projection,
/// field of view and zoom of `camera`. Throws ConfigError for an empty box.
[[nodiscard]] CameraConfig frame_bounds(const Aabb& box, CameraConfig camera);

}  // namespace beamtrace
