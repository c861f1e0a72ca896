// A conic (Palmer) scanner: a nutating or wedged rotating mirror that keeps the beam at a fixed
// angle from the optical axis while the azimuth turns, tracing a circle (on the ground an
// ellipse-like loop for a forward motion), as in airborne bathymetric and topographic ALS
// (RIEGL VQ-880-G style).
//
// Conventions (sensor frame: x forward/optical axis, y left, z up):
// - With a = off_axis_deg and the azimuth phi measured about +x from +y towards +z (right-handed
//   about x), the direction is [cos a, sin a cos phi, sin a sin phi]: the vector
//   [cos a, sin a, 0] rotated about sensor +x by phi.
// - phi_i = 2 pi frac(rotation_rate_hz * i / pulse_rate_hz): azimuth 0 (towards +y) at pulse 0,
//   one revolution per 1 / rotation_rate_hz seconds. scan_angle_deg = phi_i in degrees, wrapped
//   into [-180, 180) (it is the mirror's azimuth, not the beam's angle from x towards +y).
// - Mounted looking down ([roll pitch yaw] = [0, -pi/2, 0] on a platform flying along +x: sensor
//   x down, y left, z forward) azimuth 0 points left, +90 deg forward, +-180 right, -90 back.
// - One channel (0). Pulse times t_i = start_time_s + i / pulse_rate_hz.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

struct ConicScannerConfig {
    double pulse_rate_hz = 100'000.0;  ///< pulses per second
    double rotation_rate_hz = 50.0;    ///< mirror revolutions per second; >= 3 pulses each
    double off_axis_deg = 20.0;        ///< the beam's constant angle from sensor x, in (0, 90)
    double duration_s = 1.0;           ///< survey length; whole pulses only
    double start_time_s = 0.0;         ///< time of pulse 0 (azimuth 0)

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

class ConicScanner final : public ScanPattern {
  public:
    using Config = ConicScannerConfig;

    /// Throws ConfigError listing every problem of `config`.
    explicit ConicScanner(ConicScannerConfig config);

    [[nodiscard]] std::uint64_t pulse_count() const override { return pulse_count_; }
    [[nodiscard]] double pulse_rate_hz() const override { return config_.pulse_rate_hz; }
    [[nodiscard]] double start_time_s() const override { return config_.start_time_s; }
    [[nodiscard]] const ConicScannerConfig& config() const { return config_; }

    /// The mirror azimuth of pulse i in revolutions, in [0, 1).
    [[nodiscard]] double azimuth_turns(std::uint64_t i) const;

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;

    ConicScannerConfig config_;
    std::uint64_t pulse_count_ = 0;
};

}  // namespace beamtrace
