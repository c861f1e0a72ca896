// The pinhole camera of height-field views.
#pragma once

#include "beamtrace/core/camera_pose.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// Position in the LAS files' coordinates; yaw and pitch in degrees in beamtrace's camera
/// convention (core/camera_pose.hpp, docs/camera.md: yaw 0 looks along +x, positive yaw pans
/// right, i.e. clockwise seen from above; pitch positive up, -90 looks straight down);
/// horizontal field of view; image size in pixels. The image's "right" is horizontal whatever
/// the pitch, so looking straight down is well defined (yaw then turns the image).
struct ViewCamera {
    Vec3d position;
    double yaw_deg = 0.0;
    double pitch_deg = 0.0;
    double hfov_deg = 60.0;  ///< horizontal field of view, (0, 180) degrees
    int width = 1920;        ///< pixels, 1 to 32768
    int height = 1080;       ///< pixels, 1 to 32768

    [[nodiscard]] CameraPose pose() const { return {position, yaw_deg, pitch_deg}; }
    void set_pose(const CameraPose& p) {
        position = p.position;
        yaw_deg = p.yaw_deg;
        pitch_deg = p.pitch_deg;
    }
    /// Throws ConfigError listing every problem (size, FOV, pitch beyond +-90, non-finite values).
    void validate() const;
};

/// Pitch of overview_camera() [deg].
inline constexpr double kOverviewPitchDeg = -90.0;

/// A view of all data within [lo, hi] (the default of `view` without --camera, and the start of
/// an interactive view): looking straight down (kOverviewPitchDeg) at the box's centre, north
/// up (yaw -90, facing +y) unless the footprint turned a quarter (yaw 0, facing +x) fills the
/// frame 1.25 times larger or more, from the nearest height at which the footprint's corners at
/// the lowest height lo.z lie within 95 % of the frame. Keeps the field of view and image size
/// of `camera`.
[[nodiscard]] ViewCamera overview_camera(const Vec3d& lo, const Vec3d& hi, ViewCamera camera);

/// Unit ray directions through pixel centres; pixel (0, 0) is the top-left.
class CameraRays {
  public:
    explicit CameraRays(const ViewCamera& camera);
    [[nodiscard]] Vec3d direction(int px, int py) const { return direction_at(u(px), v(py)); }
    /// The image-plane coordinates of pixel column px and row py (direction(px, py) is
    /// direction_at(u(px), v(py)): renderers work them out once per column and row).
    [[nodiscard]] double u(int px) const { return (2.0 * (px + 0.5) / width_ - 1.0) * tan_x_; }
    [[nodiscard]] double v(int py) const { return (1.0 - 2.0 * (py + 0.5) / height_) * tan_y_; }
    [[nodiscard]] Vec3d direction_at(double u, double v) const {
        return normalize(forward_ + right_ * u + up_ * v);
    }
    [[nodiscard]] const Vec3d& forward() const { return forward_; }
    [[nodiscard]] const Vec3d& right() const { return right_; }  ///< horizontal, image right
    [[nodiscard]] const Vec3d& up() const { return up_; }        ///< image up

  private:
    Vec3d forward_, right_, up_;
    double tan_x_ = 0, tan_y_ = 0;
    double width_ = 1, height_ = 1;
};

}  // namespace beamtrace
