#include "beamtrace/render/camera.hpp"

#include <cmath>
#include <numbers>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

std::vector<std::string> CameraConfig::validate() const {
    std::vector<std::string> problems;
    constexpr int kMaxSide = 16384;
    if (width < 1 || width > kMaxSide || height < 1 || height > kMaxSide) {
        problems.push_back("image size " + std::to_string(width) + "x" + std::to_string(height) +
                           " must be 1..16384 pixels per side");
    }
    if (!(zoom > 0.0) || !std::isfinite(zoom)) {
        problems.push_back("zoom must be positive");
    }
    if (projection == Projection::pinhole && !(vfov_rad > 0.0 && vfov_rad < std::numbers::pi)) {
        problems.push_back("vertical field of view must be in (0, 180) degrees");
    }
    if (projection == Projection::orthographic &&
        !(view_width_m > 0.0 && std::isfinite(view_width_m))) {
        problems.push_back("orthographic view width must be positive");
    }
    for (double v : {position_m.x, position_m.y, position_m.z, orientation.roll_rad,
                     orientation.pitch_rad, orientation.yaw_rad}) {
        if (!std::isfinite(v)) {
            problems.push_back("camera position and orientation must be finite");
            break;
        }
    }
    return problems;
}

RollPitchYaw look_at(const Vec3d& from_m, const Vec3d& to_m, double roll_rad) {
    const Vec3d d = to_m - from_m;
    const double len = length(d);
    if (!(len > 0.0)) {
        throw ConfigError("look-at target must differ from the camera position");
    }
    const Vec3d f = d * (1.0 / len);
    // The forward axis of rpy_matrix is (cos p cos y, -cos p sin y, sin p).
    return {roll_rad, std::asin(std::fmax(-1.0, std::fmin(1.0, f.z))), std::atan2(-f.y, f.x)};
}

Camera::Camera(const CameraConfig& config) : config_(config) {
    const auto problems = config.validate();
    if (!problems.empty()) {
        std::string msg = "camera: " + problems.front();
        for (std::size_t i = 1; i < problems.size(); ++i) {
            msg += "; " + problems[i];
        }
        throw ConfigError(msg);
    }
    const Mat3 r = rpy_matrix(config.orientation);
    forward_ = sensor_to_world({1, 0, 0}, r);
    left_ = sensor_to_world({0, 1, 0}, r);
    up_ = sensor_to_world({0, 0, 1}, r);
    const double aspect = static_cast<double>(config.width) / static_cast<double>(config.height);
    if (config.projection == Projection::pinhole) {
        half_h_ = std::tan(0.5 * config.vfov_rad) / config.zoom;
        half_w_ = half_h_ * aspect;
    } else {
        half_w_ = 0.5 * config.view_width_m / config.zoom;
        half_h_ = half_w_ / aspect;
    }
}

void Camera::ray_at(double x, double y, Vec3d& origin, Vec3d& direction) const {
    // Image-plane coordinates: +1 at the left / top edge, -1 at the right / bottom edge.
    const double sy = 1.0 - 2.0 * x / config_.width;
    const double sz = 1.0 - 2.0 * y / config_.height;
    if (config_.projection == Projection::pinhole) {
        origin = config_.position_m;
        direction = normalize(forward_ + left_ * (sy * half_w_) + up_ * (sz * half_h_));
    } else {
        origin = config_.position_m + left_ * (sy * half_w_) + up_ * (sz * half_h_);
        direction = forward_;
    }
}

double Camera::pixel_area_m2() const {
    if (config_.projection != Projection::orthographic) {
        return 0.0;
    }
    const double side = 2.0 * half_w_ / config_.width;
    return side * side;
}

}  // namespace beamtrace
