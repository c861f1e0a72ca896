#include "beamtrace/sensor/image_sensor.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/image_pattern.hpp"

namespace beamtrace {
namespace {

/// Checks settings for casting one whole image of rays, which is held in memory at once.
void check(const ImageSensorConfig& c, bool scanning) {
    auto problems = c.validate(scanning);
    const std::uint64_t pixels =
        std::uint64_t(std::max(c.width, 0)) * std::uint64_t(std::max(c.height, 0));
    if (pixels > kMaxImagePixels) {
        problems.push_back("width x height (" + std::to_string(c.width) + " x " +
                           std::to_string(c.height) + ") must be at most " +
                           std::to_string(kMaxImagePixels) +
                           " rays (e.g. 8192 x 8192), the limit of one image");
    }
    if (!problems.empty()) {
        std::string msg = "invalid sensor settings:";
        for (const auto& p : problems) {
            msg += " " + p + ";";
        }
        msg.pop_back();
        throw ConfigError(msg);
    }
}

template <class DirFn>
RayBatch cast(const ImageSensorConfig& c, DirFn dir_fn) {
    RayBatch rays;
    const auto n = static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height);
    rays.resize(n);
    const Mat3 r = rpy_matrix(c.orientation);
    for (int u = 0; u < c.width; ++u) {
        for (int v = 0; v < c.height; ++v) {
            const Vec3d d_cam = dir_fn(u, v);
            rays.set(ray_index(u, v, c.height), c.position_m, sensor_to_world(d_cam, r));
        }
    }
    return rays;
}

}  // namespace

std::vector<std::string> ImageSensorConfig::validate(bool scanning) const {
    std::vector<std::string> p;
    if (width < 1) {
        p.push_back("width must be at least 1 (got " + std::to_string(width) + ")");
    }
    if (height < 1) {
        p.push_back("height must be at least 1 (got " + std::to_string(height) + ")");
    }
    if (width >= 1 && height >= 1 &&
        static_cast<double>(width) * static_cast<double>(height) > 4.0e9) {
        p.push_back("width x height must be below 4e9 rays");
    }
    const double pi = std::numbers::pi;
    const double hmax = scanning ? 2.0 * pi : pi;
    const double vmax = pi;
    if (!(hfov_rad > 0.0 && (scanning ? hfov_rad <= hmax : hfov_rad < hmax))) {
        p.push_back("hfov must be in (0, " + std::string(scanning ? "2 pi]" : "pi)") +
                    " radians (got " + std::to_string(hfov_rad) + ")");
    }
    if (!(vfov_rad > 0.0 && (scanning ? vfov_rad <= vmax : vfov_rad < vmax))) {
        p.push_back("vfov must be in (0, " + std::string(scanning ? "pi]" : "pi)") +
                    " radians (got " + std::to_string(vfov_rad) + ")");
    }
    if (!std::isfinite(position_m.x) || !std::isfinite(position_m.y) ||
        !std::isfinite(position_m.z)) {
        p.push_back("position must be finite");
    }
    if (!std::isfinite(orientation.roll_rad) || !std::isfinite(orientation.pitch_rad) ||
        !std::isfinite(orientation.yaw_rad)) {
        p.push_back("orientation must be finite");
    }
    return p;
}

double linspace_at(double a, double b, int n, int i) {
    if (n == 1) {
        return 0.5 * (a + b);
    }
    if (i == n - 1) {
        return b;
    }
    return a + static_cast<double>(i) * (b - a) / static_cast<double>(n - 1);
}

RayBatch cast_rays_pinhole(const ImageSensorConfig& c) {
    check(c, false);
    const double y0 = std::tan(0.5 * c.hfov_rad);
    const double z0 = std::tan(0.5 * c.vfov_rad);
    return cast(c, [&](int u, int v) {
        return normalize(
            Vec3d{1.0, linspace_at(y0, -y0, c.width, u), linspace_at(z0, -z0, c.height, v)});
    });
}

RayBatch cast_rays_scan(const ImageSensorConfig& c) {
    check(c, true);
    return cast(c, [&](int u, int v) {
        const double phi = linspace_at(0.5 * c.hfov_rad, -0.5 * c.hfov_rad, c.width, u);
        const double theta = linspace_at(0.5 * c.vfov_rad, -0.5 * c.vfov_rad, c.height, v);
        return Vec3d{std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi),
                     std::sin(theta)};
    });
}

}  // namespace beamtrace
