// Cameras for shaded images: a pinhole and an orthographic projection with the assignment's
// pan/tilt/track/zoom as plain parameters.
//
// Camera frame as in the ladar report: x forward (optical axis), y left, z up; the orientation
// [roll pitch yaw] rotates it into the world like `scan --orientation` and every other
// orientation in beamtrace (docs/camera.md, core/camera_pose.hpp: positive yaw pans to the
// right, clockwise seen from above; positive pitch tilts up). Pixels are row-major, (0, 0) at the
// top left; rays pass through pixel centres.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/mat3.hpp"
#include "beamtrace/core/rotation.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

enum class Projection : std::uint8_t { pinhole, orthographic };

struct CameraConfig {
    Projection projection = Projection::pinhole;
    Vec3d position_m{0, 0, 0};  ///< track: the pinhole, or the centre of the orthographic view
    RollPitchYaw orientation;   ///< pan = yaw, tilt = pitch, and roll, radians
    double vfov_rad = 0.8;      ///< pinhole: vertical field of view at zoom 1, in (0, pi)
    double view_width_m = 2.0;  ///< orthographic: width of the view at zoom 1, > 0
    double zoom = 1.0;          ///< magnification: divides tan(vfov/2) or the view width
    int width = 640;            ///< pixels, 1..16384
    int height = 480;           ///< pixels, 1..16384

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// The orientation that looks from `from_m` at `to_m` with the given roll (throws ConfigError
/// when the points coincide).
[[nodiscard]] RollPitchYaw look_at(const Vec3d& from_m, const Vec3d& to_m, double roll_rad = 0.0);

/// A validated camera that makes the ray of any image point.
class Camera {
  public:
    /// Throws ConfigError listing every problem of `config`.
    explicit Camera(const CameraConfig& config);

    [[nodiscard]] const CameraConfig& config() const { return config_; }
    [[nodiscard]] int width() const { return config_.width; }
    [[nodiscard]] int height() const { return config_.height; }
    [[nodiscard]] std::size_t pixel_count() const {
        return static_cast<std::size_t>(config_.width) * static_cast<std::size_t>(config_.height);
    }
    /// World directions of the camera axes.
    [[nodiscard]] const Vec3d& forward() const { return forward_; }
    [[nodiscard]] const Vec3d& left() const { return left_; }
    [[nodiscard]] const Vec3d& up() const { return up_; }

    /// The ray through image point (x, y) in pixel units ((0.5, 0.5) is the centre of the top-left
    /// pixel). Directions are unit length.
    void ray_at(double x, double y, Vec3d& origin, Vec3d& direction) const;
    /// The ray through the centre of pixel (column, row).
    void pixel_ray(int column, int row, Vec3d& origin, Vec3d& direction) const {
        ray_at(column + 0.5, row + 0.5, origin, direction);
    }
    /// Orthographic: the area one pixel covers on a plane facing the camera (square pixels);
    /// 0 for a pinhole.
    [[nodiscard]] double pixel_area_m2() const;

  private:
    CameraConfig config_;
    Vec3d forward_, left_, up_;
    double half_w_ = 0.0;  ///< half the image width: tan(hfov/2) or metres
    double half_h_ = 0.0;
};

}  // namespace beamtrace
