// A fibre-array line scanner (TopoSys Falcon style): `fibres` optical fibres laid along a line
// in the focal plane, fired one after the other by a rotating switch, make a fan of fixed beams
// across track; the platform's motion lays the lines side by side.
//
// Conventions (sensor frame: x forward/optical axis, y left, z up):
// - Fibre k looks at the across-track angle a_k = -fan / 2 + k fan / (fibres - 1) (fan =
//   fan_deg): fibre 0 at -fan / 2 (towards -y), the last at +fan / 2. Its direction is
//   [cos a_k, sin a_k, 0] (the line scanner's plane); mount it as the line scanner
//   ([0, -pi/2, 0]) for lines across track.
// - Pulse i fires fibre k = i mod fibres (the fibres in sequence, 0 first), at t_i =
//   start_time_s + i / pulse_rate_hz: a line of every fibre takes fibres / pulse_rate_hz.
// - channel = k (the fibre), scan_angle_deg = a_k.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

struct FibreScannerConfig {
    double pulse_rate_hz = 83'000.0;  ///< pulses per second (all fibres together)
    int fibres = 127;                 ///< fibres along the line, in [2, 65536]
    double fan_deg = 14.0;            ///< full width of the fan, in (0, 180)
    double duration_s = 1.0;          ///< survey length; whole pulses only
    double start_time_s = 0.0;        ///< time of pulse 0 (fibre 0)

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

class FibreScanner final : public ScanPattern {
  public:
    using Config = FibreScannerConfig;

    /// Throws ConfigError listing every problem of `config`.
    explicit FibreScanner(FibreScannerConfig config);

    [[nodiscard]] std::uint64_t pulse_count() const override { return pulse_count_; }
    [[nodiscard]] double pulse_rate_hz() const override { return config_.pulse_rate_hz; }
    [[nodiscard]] double start_time_s() const override { return config_.start_time_s; }
    [[nodiscard]] const FibreScannerConfig& config() const { return config_; }

    /// The across-track angle of fibre k, in degrees.
    [[nodiscard]] double fibre_angle_deg(int k) const;

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;

    FibreScannerConfig config_;
    std::uint64_t pulse_count_ = 0;
};

}  // namespace beamtrace
