#include "beamtrace/physics/noise.hpp"

#include <cmath>

#include "beamtrace/core/rng.hpp"
#include "beamtrace/physics/beam_divergence.hpp"

namespace beamtrace {
namespace {

bool non_negative(double v) {
    return v >= 0 && std::isfinite(v);
}

}  // namespace

std::vector<std::string> NoiseConfig::validate() const {
    std::vector<std::string> p;
    const auto check = [&](double v, const char* what) {
        if (!non_negative(v)) {
            p.push_back(std::string("noise: ") + what + " must be zero or positive");
        }
    };
    check(range_sigma_m, "range_sigma_m");
    check(range_sigma_per_m, "range_sigma_per_m");
    check(angle_jitter_rad, "angle_jitter_rad");
    if (!(dropout_probability >= 0 && dropout_probability <= 1)) {
        p.emplace_back("noise: dropout_probability must be in [0, 1]");
    }
    for (auto& problem : georeferencing.validate()) {
        p.push_back(std::move(problem));
    }
    return p;
}

bool NoiseConfig::none() const {
    return range_sigma_m == 0 && range_sigma_per_m == 0 && angle_jitter_rad == 0 &&
           dropout_probability == 0 && georeferencing.none();
}

double range_sigma_m(const NoiseConfig& config, double range_m) {
    // Independent error sources add in quadrature.
    return std::hypot(config.range_sigma_m, config.range_sigma_per_m * range_m);
}

double range_noise_m(const NoiseConfig& config, std::uint64_t seed, std::uint64_t pulse_index,
                     std::uint32_t return_index, double range_m) {
    const double sigma = range_sigma_m(config, range_m);
    if (!(sigma > 0)) {
        return 0.0;
    }
    CounterRng rng(seed, pulse_index, return_index, RngStream::range_noise);
    return sigma * rng.normal();
}

bool pulse_dropped(const NoiseConfig& config, std::uint64_t seed, std::uint64_t pulse_index) {
    if (!(config.dropout_probability > 0)) {
        return false;
    }
    CounterRng rng(seed, pulse_index, 0, RngStream::dropout);
    return rng.uniform() < config.dropout_probability;
}

Vec3d jitter_direction(const NoiseConfig& config, std::uint64_t seed, std::uint64_t pulse_index,
                       const Vec3d& axis) {
    if (!(config.angle_jitter_rad > 0)) {
        return axis;
    }
    CounterRng rng(seed, pulse_index, 0, RngStream::angle_jitter);
    const double a = config.angle_jitter_rad * rng.normal();
    const double b = config.angle_jitter_rad * rng.normal();
    Vec3d e1, e2;
    orthonormal_basis(axis, e1, e2);
    // Tilt by the angle sqrt(a^2 + b^2) towards a e1 + b e2 (exact, not small-angle).
    const double tilt = std::sqrt(a * a + b * b);
    if (!(tilt > 0)) {
        return axis;
    }
    const Vec3d towards = (e1 * a + e2 * b) * (1.0 / tilt);
    return normalize(axis * std::cos(tilt) + towards * std::sin(tilt));
}

}  // namespace beamtrace
