// Georeferencing errors: the difference between the pose a LiDAR system truly had and the pose
// its GNSS/INS and calibration report (Schaer et al. 2007, "In-flight accuracy estimation for
// airborne lidar data"; Glennie 2007, "Rigorous 3D error analysis of kinematic scanning LIDAR
// systems"). The beam is traced from the TRUE pose; the point is placed with the MEASURED one:
//
//   platform_meas = { p + dp(t),  q * exp([dtheta(t)]) }       dp: world axes, dtheta: body axes
//   mount_meas    = { L + dL,     M * B(boresight_error) }      fixed calibration errors
//   sensor_meas   = platform_meas * mount_meas
//   point         = sensor_meas.position + range * sensor_meas.attitude * pattern_direction
//
// Random errors dp (sigma position_sigma_m per world axis) and dtheta (sigma attitude_sigma_rad
// about each body axis) are, per axis, either white (correlation_time_s = 0: drawn afresh per
// pulse, streams position_noise / attitude_noise keyed by the pulse index) or a first-order
// Gauss-Markov process (correlation tau = correlation_time_s, autocorrelation e^(-|lag|/tau)).
//
// The Gauss-Markov process is sampled on a fixed time grid t_n = n h, h = tau / 8, each node
// evaluated DIRECTLY (never by a recursion started where a block happens to begin) from the
// truncated moving-average form of the AR(1) process
//   x_n = sigma sqrt(1 - a^2) sum_{k=0..K} a^k w_{n-k},   a = exp(-h / tau),  a^K < 1e-9,
// with w_m = CounterRng(seed, m, axis, gauss_markov_{position,attitude}).normal(). Between two
// nodes the value is the linear interpolation rescaled to keep the variance sigma^2:
//   x(t) = (w0 x_n + w1 x_{n+1}) / sqrt(w0^2 + w1^2 + 2 w0 w1 a),  w1 = t/h - n, w0 = 1 - w1.
// So a pulse's error depends only on (config, seed, pulse time): the same on any number of
// threads and in any chunking of the pulses, bit for bit.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/quat.hpp"
#include "beamtrace/core/rng.hpp"
#include "beamtrace/core/rotation.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

/// Errors of the measured pose. Defaults: none (points are placed with the true pose).
struct GeoreferencingConfig {
    double position_sigma_m = 0.0;    ///< std of the GNSS position error per world axis [m]
    double attitude_sigma_rad = 0.0;  ///< std of the INS attitude error about each body axis
    double correlation_time_s = 0.0;  ///< Gauss-Markov correlation time tau [s]; 0: white
    Vec3d lever_arm_error_m;          ///< measured minus true lever arm, platform frame [m]
    RollPitchYaw boresight_error;     ///< measured boresight = true * this, sensor frame [rad]

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
    /// True when the random errors are off (sigmas zero).
    [[nodiscard]] bool no_random_error() const;
    /// True when every error is off: the measured pose is the true pose.
    [[nodiscard]] bool none() const;
};

/// The random part of a pulse's pose error.
struct PoseError {
    Vec3d position_m;    ///< added to the platform position, world axes [m]
    Vec3d attitude_rad;  ///< rotation vector of the error, platform body axes [rad]
};

/// Nodes of the Gauss-Markov grid already evaluated, reused by the next pulses. Plain values:
/// one per thread, never shared. Only speed depends on it, never a result.
struct GaussMarkovCache {
    std::int64_t first_node = 0;  ///< index of nodes[0]
    std::vector<Vec3d> nodes;     ///< x_n per axis, first_node + i
    std::vector<double> w;        ///< scratch: the white normals of one range of nodes
};

/// A first-order Gauss-Markov process of standard deviation sigma and correlation time tau,
/// per axis (x, y, z), on the grid described above.
class GaussMarkovGrid {
  public:
    static constexpr int kNodesPerTau = 8;  ///< h = tau / 8

    GaussMarkovGrid(double sigma, double tau_s, RngStream stream);

    [[nodiscard]] double step_s() const { return h_s_; }
    /// The node x_n (three axes), by the direct sum.
    [[nodiscard]] Vec3d node(std::uint64_t seed, std::int64_t n) const;
    /// The process at `time_s`, through `cache` (filled from `seed`; pass the same seed).
    [[nodiscard]] Vec3d at(std::uint64_t seed, double time_s, GaussMarkovCache& cache) const;
    /// Evaluates the nodes [lo, hi] into `cache` at once (cheaper than node by node).
    void fill(std::uint64_t seed, std::int64_t lo, std::int64_t hi, GaussMarkovCache& cache) const;

  private:
    double sigma_ = 0.0, h_s_ = 0.0, a_ = 0.0;
    RngStream stream_;
    std::vector<double> weights_;  ///< sigma sqrt(1 - a^2) a^k, k = 0..K
};

/// Working space of platform_errors(), one per thread.
struct PlatformErrorScratch {
    GaussMarkovCache position, attitude;
};

/// The random pose errors of pulses first_pulse + i fired at time_s[i] into out[i]
/// (out.size() == time_s.size()). Zero where the sigmas are zero.
void platform_errors(const GeoreferencingConfig& config, std::uint64_t seed,
                     std::uint64_t first_pulse, std::span<const double> time_s,
                     std::span<PoseError> out, PlatformErrorScratch& scratch);

/// The platform pose the system measures: `platform` with the error `e` applied.
[[nodiscard]] Pose measured_platform_pose(const Pose& platform, const PoseError& e);

/// The sensor-to-platform mount the system believes: lever arm + error, boresight * error.
[[nodiscard]] Pose measured_mount(const GeoreferencingConfig& config, const Pose& mount);

/// measured_platform_pose(platform, e) * measured_mount(config, mount): the sensor pose the
/// system records for one pulse.
[[nodiscard]] Pose measured_sensor_pose(const GeoreferencingConfig& config, const Pose& platform,
                                        const Pose& mount, const PoseError& e);

}  // namespace beamtrace
