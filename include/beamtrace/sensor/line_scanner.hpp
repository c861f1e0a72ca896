// An airborne line scanner: one beam swept across track by a mirror (oscillating or rotating
// polygon); the platform's motion lays the scan lines side by side.
//
// Conventions (sensor frame: x forward/optical axis, y left, z up):
// - The mirror sweeps the beam in the sensor's x-y plane: at scan angle s the direction is
//   [cos s, sin s, 0], i.e. the optical axis rotated about sensor +z by s. s = 0 is the optical
//   axis; positive s is towards +y (left). scan_angle_deg = s in degrees (see PulseBatch about
//   the LAS sign).
// - To look at nadir with lines across track, mount the sensor with the report's attitude
//   [roll pitch yaw] = [0, -pi/2, 0] on a platform flying along its +x (trajectory.hpp): sensor
//   x then points down, sensor y stays the platform's left and sensor z points forward.
// - scan_rate_hz is the MIRROR FREQUENCY, as data sheets and HELIOS++ give it: mirror periods
//   per second. A sawtooth period is one line; an oscillating (triangle, sinusoid) period is two
//   lines, one each way: 50 Hz = 100 lines/s. With T = 1 / lines_per_s() (the line period) and
//   tau = t - start_time_s:
//     sawtooth: s = -max + 2 max frac(tau / T): each line ramps from -max (reached exactly at
//               the line's start) towards +max (approached, not reached) and flies back at once;
//     triangle: mirror period 2T, s = max (1 - 4 |frac(tau / 2T) - 1/2|): -max at even line
//               starts, +max at odd ones, linear in between (lines alternate direction). With a
//               turn_duration_s D > 0 the mirror turns at finite acceleration: within a line
//               (u = time since its start, h = D / 2, speed w = 2 max / (T - h), acceleration
//               w / h) s = -max + w u^2 / (2h) for u < h, -max + w h / 2 + w (u - h) in the
//               middle, +max - w (T - u)^2 / (2h) for u > T - h (odd lines negated): the
//               angle is continuous, the speed goes linearly from +w to -w over D around each
//               end (HELIOS++ spends its turningPulses the same way). Pulses fired during the
//               turn point at those slowing angles and are recorded like any other;
//     sinusoid: mirror period 2T, s = -max cos(2 pi tau / 2T): the same turning points as the
//               triangle, sinusoidal in between.
//   Line n spans [start_time_s + n T, start_time_s + (n + 1) T). A sawtooth line thus sweeps
//   from right (-y) to left (+y): LAS scan direction flag 0 for a nadir mount.
// - One channel (0). Pulse times t_i = start_time_s + i / pulse_rate_hz.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

enum class ScanWaveform { sawtooth, sinusoid, triangle };

/// "sawtooth", "sinusoid", "triangle".
[[nodiscard]] std::string_view to_string(ScanWaveform waveform);
/// The waveform named `name` (as to_string writes it); throws ConfigError listing the choices.
[[nodiscard]] ScanWaveform parse_scan_waveform(std::string_view name);

struct LineScannerConfig {
    double pulse_rate_hz = 100'000.0;  ///< pulses per second
    double scan_rate_hz = 100.0;       ///< mirror periods per second (see the waveforms above)
    double scan_angle_max_deg = 20.0;  ///< half field of view, in (0, 90)
    ScanWaveform waveform = ScanWaveform::sawtooth;
    /// triangle only: time the mirror takes to turn at each end (speed +w to -w), in s, in
    /// [0, line period); 0: an instantaneous turn.
    double turn_duration_s = 0.0;
    double duration_s = 1.0;    ///< survey length; whole pulses only
    double start_time_s = 0.0;  ///< time of pulse 0 and of line 0's start

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;

    /// Scan lines per second: scan_rate_hz for a sawtooth, 2 x scan_rate_hz for an oscillating
    /// mirror (triangle, sinusoid).
    [[nodiscard]] double lines_per_s() const {
        return waveform == ScanWaveform::sawtooth ? scan_rate_hz : 2.0 * scan_rate_hz;
    }
};

class LineScanner final : public ScanPattern {
  public:
    using Config = LineScannerConfig;

    /// Throws ConfigError listing every problem of `config`.
    explicit LineScanner(LineScannerConfig config);

    [[nodiscard]] std::uint64_t pulse_count() const override { return pulse_count_; }
    [[nodiscard]] double pulse_rate_hz() const override { return config_.pulse_rate_hz; }
    [[nodiscard]] double start_time_s() const override { return config_.start_time_s; }
    [[nodiscard]] const LineScannerConfig& config() const { return config_; }

    /// The scan angle in degrees at time `time_s` (the waveform; defined for any time).
    [[nodiscard]] double scan_angle_deg_at(double time_s) const;
    /// The scan line that pulse i belongs to.
    [[nodiscard]] std::uint64_t line_of_pulse(std::uint64_t i) const;
    /// The start time of scan line n: start_time_s + n / lines_per_s().
    [[nodiscard]] double line_start_time_s(std::uint64_t n) const;

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;
    /// The scan angle in degrees at `lines` = (t - start_time_s) * lines_per_s().
    [[nodiscard]] double angle_at_lines(double lines) const;
    /// The triangle with turns (turn_duration_s > 0) at `lines`.
    [[nodiscard]] double turning_angle_at_lines(double lines) const;

    LineScannerConfig config_;
    std::uint64_t pulse_count_ = 0;
    double lines_per_s_ = 0.0;  ///< config_.lines_per_s()
};

}  // namespace beamtrace
