// The ladar simulator report's two image-type sensors (eqs 2.4-2.8, Appendix A.3/A.4).
//
// Sensor frame: x forward (optical axis), y left, z up; orientation [roll pitch yaw] rotates it
// into the world as the report's `D * (Rx*Ry*Rz)`. Rays are in the report's order: column-major,
// ray index = u * height + v, with u the column (0 = left) and v the row (0 = top).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/rotation.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct ImageSensorConfig {
    Vec3d position_m{0.0, 0.0, 0.0};  ///< ray origin (principal point)
    RollPitchYaw orientation;         ///< radians; zeros look along +x with z up
    int width = 512;                  ///< columns (azimuth samples)
    int height = 256;                 ///< rows (elevation samples)
    double hfov_rad = 1.0;            ///< horizontal field of view
    double vfov_rad = 0.5;            ///< vertical field of view

    /// Every problem with these settings for the given pattern ("pinhole" allows FOVs below pi,
    /// "scan" up to 2 pi horizontally and pi vertically); empty when valid.
    [[nodiscard]] std::vector<std::string> validate(bool scanning) const;
};

/// Matlab's linspace(a, b, n) for n >= 2; the centre (a + b) / 2 for n == 1 (the report's code
/// would return b, offsetting a single row or column).
[[nodiscard]] double linspace_at(double a, double b, int n, int i);

/// `castRaysPinhole`: directions normalize([1, y_u, z_v]) with y_u = linspace(tan(hfov/2),
/// -tan(hfov/2), w) and z_v = linspace(tan(vfov/2), -tan(vfov/2), h). Throws ConfigError.
[[nodiscard]] RayBatch cast_rays_pinhole(const ImageSensorConfig& config);

/// `castRaysScan`: directions [cos t cos p, cos t sin p, sin t] with p = linspace(hfov/2,
/// -hfov/2, w) and t = linspace(vfov/2, -vfov/2, h). Throws ConfigError.
[[nodiscard]] RayBatch cast_rays_scan(const ImageSensorConfig& config);

/// Index of the ray for image pixel (row v, column u).
[[nodiscard]] inline std::size_t ray_index(int u, int v, int height) {
    return static_cast<std::size_t>(u) * static_cast<std::size_t>(height) +
           static_cast<std::size_t>(v);
}

}  // namespace beamtrace
