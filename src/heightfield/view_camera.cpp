#include "beamtrace/heightfield/view_camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

void ViewCamera::validate() const {
    std::string problems;
    if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z) ||
        !std::isfinite(yaw_deg)) {
        problems += "position and yaw must be finite numbers; ";
    }
    if (!(pitch_deg >= -90.0 && pitch_deg <= 90.0)) {
        problems += "pitch " + std::to_string(pitch_deg) + " is outside -90 to 90 degrees; ";
    }
    if (!(hfov_deg > 0.0 && hfov_deg < 180.0)) {
        problems += "field of view " + std::to_string(hfov_deg) + " is outside (0, 180) degrees; ";
    }
    if (width < 1 || height < 1 || width > 32768 || height > 32768) {
        problems += "image size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is outside 1 to 32768 pixels; ";
    }
    if (!problems.empty()) {
        problems.resize(problems.size() - 2);
        throw ConfigError("camera: " + problems);
    }
}

ViewCamera overview_camera(const Vec3d& lo, const Vec3d& hi, ViewCamera camera) {
    const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
    camera.position = {0.5 * (lo.x + hi.x) - 0.3 * (hi.x - lo.x), 0.5 * (lo.y + hi.y),
                       hi.z + 0.1 * extent};
    camera.yaw_deg = 0.0;
    camera.pitch_deg = -30.0;
    return camera;
}

CameraRays::CameraRays(const ViewCamera& camera) {
    const double deg = std::numbers::pi / 180.0;
    const double yaw = camera.yaw_deg * deg;
    forward_ = camera.pose().forward();
    right_ = {-std::sin(yaw), -std::cos(yaw), 0.0};  // horizontal, 90 degrees right of the yaw
    up_ = cross(right_, forward_);
    width_ = camera.width;
    height_ = camera.height;
    tan_x_ = std::tan(camera.hfov_deg * deg / 2.0);
    tan_y_ = tan_x_ * height_ / width_;
}

}  // namespace beamtrace
