// Measurement noise and dropouts, all drawn from the counter RNG (core/rng.hpp) keyed by
// (seed, pulse index, sub-ray or return index, stream): the same seed gives the same survey on
// any number of threads, in any chunking.
//
// - Range noise: Gaussian, sigma(R) = sqrt(range_sigma_m^2 + (range_sigma_per_m R)^2) (independent
//   errors in quadrature), added to every return's range (key: return index, stream range_noise).
// - Angular jitter: the beam axis is tilted by a 2-D Gaussian offset of angle_jitter_rad per
//   axis, perpendicular to it (key: sub-ray 0, stream angle_jitter) before the sub-rays are laid
//   around it.
// - Platform (georeferencing) errors: georeferencing.hpp. The beam is traced from the true pose
//   and the point placed with the measured one (GNSS/INS error, white or Gauss-Markov in time,
//   plus fixed lever-arm and boresight errors).
// - Dropouts: each pulse is lost with probability dropout_probability (stream dropout).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/physics/georeferencing.hpp"

namespace beamtrace {

struct NoiseConfig {
    double range_sigma_m = 0.0;           ///< constant part a of sigma = sqrt(a^2 + (b R)^2)
    double range_sigma_per_m = 0.0;       ///< range-proportional part b (e.g. 1e-4: 1 cm at 100 m)
    double angle_jitter_rad = 0.0;        ///< std of the beam axis tilt, per perpendicular axis
    double dropout_probability = 0.0;     ///< chance a pulse gives no return at all, [0, 1]
    GeoreferencingConfig georeferencing;  ///< errors of the measured pose (none by default)

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
    /// True when every noise source is off.
    [[nodiscard]] bool none() const;
};

/// sigma(R) = sqrt(a^2 + (b R)^2), a = range_sigma_m, b = range_sigma_per_m: the constant and
/// the range-proportional errors are independent, so they add in quadrature.
[[nodiscard]] double range_sigma_m(const NoiseConfig& config, double range_m);

/// The range error of return `return_index` of pulse `pulse_index` at range `range_m` [m].
[[nodiscard]] double range_noise_m(const NoiseConfig& config, std::uint64_t seed,
                                   std::uint64_t pulse_index, std::uint32_t return_index,
                                   double range_m);

/// True when pulse `pulse_index` is dropped.
[[nodiscard]] bool pulse_dropped(const NoiseConfig& config, std::uint64_t seed,
                                 std::uint64_t pulse_index);

/// The unit beam axis `axis` tilted by the pulse's angular jitter (axis itself if none).
[[nodiscard]] Vec3d jitter_direction(const NoiseConfig& config, std::uint64_t seed,
                                     std::uint64_t pulse_index, const Vec3d& axis);

}  // namespace beamtrace
