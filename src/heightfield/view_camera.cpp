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

namespace {

/// Whether the four corners of the footprint of [lo, hi] at height lo.z (the ground, not the
/// highest outlier) lie within `margin` of the frame of `camera`.
bool frames_footprint(const ViewCamera& camera, const Vec3d& lo, const Vec3d& hi, double margin) {
    const CameraRays rays(camera);
    const double deg = std::numbers::pi / 180.0;
    const double tan_x = std::tan(camera.hfov_deg * deg / 2.0) * margin;
    const double tan_y = tan_x * camera.height / camera.width;
    const Vec3d right = rays.right();
    const Vec3d up = rays.up();
    for (int c = 0; c < 4; ++c) {
        const Vec3d p((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, lo.z);
        const Vec3d v = p - camera.position;
        const double z = dot(v, rays.forward());
        if (!(z > 0) || std::abs(dot(v, right)) > tan_x * z || std::abs(dot(v, up)) > tan_y * z) {
            return false;
        }
    }
    return true;
}

}  // namespace

ViewCamera overview_camera(const Vec3d& lo, const Vec3d& hi, ViewCamera camera) {
    // North up (facing +y, yaw -90: x to the right, like a map), unless the footprint turned
    // a quarter (facing +x, yaw 0: y across) fills the frame a quarter larger or more.
    const double dx = std::max(hi.x - lo.x, 1e-9), dy = std::max(hi.y - lo.y, 1e-9);
    const double w = camera.width, h = camera.height;
    const double north_up = std::min(w / dx, h / dy), turned = std::min(w / dy, h / dx);
    camera.yaw_deg = turned >= 1.25 * north_up ? 0.0 : -90.0;
    camera.pitch_deg = kOverviewPitchDeg;
    const Vec3d centre = (lo + hi) * 0.5;
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-9});
    camera.position = centre;
    const Vec3d back = CameraRays(camera).forward() * -1.0;
    // The nearest distance from the centre that frames the box (bisection: farther frames it
    // more surely), then a little margin.
    double near = 0.0, far = 100.0 * extent;
    for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (near + far);
        camera.position = centre + back * mid;
        (frames_footprint(camera, lo, hi, 0.95) ? far : near) = mid;
    }
    camera.position = centre + back * far;
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
