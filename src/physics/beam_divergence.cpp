#include "beamtrace/physics/beam_divergence.hpp"

#include <cassert>
#include <cmath>
#include <numbers>

namespace beamtrace {

std::vector<std::string> BeamConfig::validate() const {
    std::vector<std::string> p;
    if (!(divergence_rad >= 0) || !(divergence_rad < 0.5)) {
        p.emplace_back("beam: divergence_rad must be in [0, 0.5)");
    }
    if (rings < 0 || rings > 20) {
        p.emplace_back("beam: rings must be in [0, 20]");
    }
    return p;
}

std::size_t sub_ray_count(const BeamConfig& config) {
    if (!(config.divergence_rad > 0) || config.rings <= 0) {
        return 1;
    }
    const auto r = static_cast<std::size_t>(config.rings);
    return 1 + 3 * r * (r + 1);
}

std::vector<SubRayOffset> beam_pattern(const BeamConfig& config) {
    std::vector<SubRayOffset> out;
    if (!(config.divergence_rad > 0) || config.rings <= 0) {
        out.push_back({});
        return out;
    }
    const double w = config.divergence_rad / 2.0;  // 1/e^2 half-angle
    const double d = w / config.rings;
    // Fraction of the profile inside off-axis angle t: 1 - exp(-2 t^2 / w^2).
    const auto cdf = [w](double t) { return 1.0 - std::exp(-2.0 * t * t / (w * w)); };
    out.reserve(sub_ray_count(config));
    double total = 0.0;
    for (int k = 0; k <= config.rings; ++k) {
        const double lo = k == 0 ? 0.0 : (k - 0.5) * d;
        const double hi = (k + 0.5) * d;
        const int count = k == 0 ? 1 : 6 * k;
        const double share = (cdf(hi) - cdf(lo)) / count;
        const double step = 2.0 * std::numbers::pi / count;
        const double phase = (k % 2 == 1) ? step / 2.0 : 0.0;
        for (int j = 0; j < count; ++j) {
            out.push_back({k * d, k == 0 ? 0.0 : phase + j * step, share});
            total += share;
        }
    }
    for (auto& s : out) {
        s.weight /= total;
    }
    return out;
}

void orthonormal_basis(const Vec3d& n, Vec3d& e1, Vec3d& e2) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    e1 = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    e2 = {b, sign + n.y * n.y * a, -n.y};
}

void sub_ray_directions(const Vec3d& axis, std::span<const SubRayOffset> pattern,
                        std::span<Vec3d> out) {
    assert(out.size() == pattern.size());
    Vec3d e1, e2;
    orthonormal_basis(axis, e1, e2);
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        const SubRayOffset& s = pattern[i];
        const double st = std::sin(s.off_axis_rad), ct = std::cos(s.off_axis_rad);
        out[i] = normalize(axis * ct +
                           (e1 * std::cos(s.azimuth_rad) + e2 * std::sin(s.azimuth_rad)) * st);
    }
}

std::vector<Vec3d> beam_frame_directions(std::span<const SubRayOffset> pattern) {
    std::vector<Vec3d> out;
    out.reserve(pattern.size());
    for (const auto& s : pattern) {
        const double st = std::sin(s.off_axis_rad);
        out.push_back(
            {st * std::cos(s.azimuth_rad), st * std::sin(s.azimuth_rad), std::cos(s.off_axis_rad)});
    }
    return out;
}

void sub_ray_directions(const Vec3d& axis, std::span<const Vec3d> beam_frame,
                        std::span<Vec3d> out) {
    assert(out.size() == beam_frame.size());
    Vec3d e1, e2;
    orthonormal_basis(axis, e1, e2);
    for (std::size_t i = 0; i < beam_frame.size(); ++i) {
        const Vec3d& b = beam_frame[i];
        out[i] = e1 * b.x + e2 * b.y + axis * b.z;
    }
}

}  // namespace beamtrace
