// A spinning multi-beam LiDAR (Velodyne, Ouster, Hesai style).
//
// Conventions (sensor frame: x forward, y left, z up):
// - The head spins about the sensor z axis. Azimuth 0 is the sensor +x axis and azimuth grows
//   towards +y (counter-clockwise seen from above); with `spin_clockwise` the head turns the
//   other way (azimuth decreasing over time), as real Velodyne and Ouster heads do.
// - Beam b has elevation beam_elevations_deg[b] (positive up) and fires with channel = b.
//   Its direction at azimuth a is [cos e cos a, cos e sin a, sin e], the report's scan formula.
// - Pulse i is beam b = i % beams of firing k = i / beams. Beams are STAGGERED: every pulse has
//   its own time t_i = start_time_s + i / pulse_rate_hz, and its azimuth is the head's angle at
//   that time plus the beam's azimuth offset: a_i = start_azimuth_deg +/- (k + b / beams) *
//   azimuth_resolution_deg + beam_azimuth_offsets_deg[b]. So each beam steps by exactly
//   azimuth_resolution_deg per firing and the head's rotation during a firing is modelled.
// - Firing rate = rotation_rate_hz * 360 / azimuth_resolution_deg; pulse rate = beams x firing
//   rate; firings per revolution = 360 / azimuth_resolution_deg.
// - scan_angle_deg = the pulse's azimuth a_i wrapped into [-180, 180).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

struct RotatingScannerConfig {
    /// Elevation of each beam in degrees (positive up), in channel order; in [-90, 90].
    std::vector<double> beam_elevations_deg;
    /// Azimuth offset of each beam in degrees (empty: all 0; else one per beam).
    std::vector<double> beam_azimuth_offsets_deg;
    double rotation_rate_hz = 10.0;       ///< revolutions per second
    double azimuth_resolution_deg = 0.2;  ///< head rotation between firings, (0, 360]
    double start_azimuth_deg = 0.0;       ///< head azimuth at start_time_s
    bool spin_clockwise = false;          ///< false: azimuth grows towards +y over time
    double duration_s = 0.1;              ///< survey length; whole firings only
    double start_time_s = 0.0;            ///< time of pulse 0

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;

    [[nodiscard]] double firing_rate_hz() const {
        return rotation_rate_hz * 360.0 / azimuth_resolution_deg;
    }
    [[nodiscard]] double pulse_rate_hz() const {
        return static_cast<double>(beam_elevations_deg.size()) * firing_rate_hz();
    }
    /// Whole firings in duration_s (each firing is one pulse of every beam).
    [[nodiscard]] std::uint64_t firing_count() const;
};

/// Velodyne VLP-16 like: 16 beams from -15 to +15 degrees every 2 degrees, in the VLP-16 laser
/// ID order (-15, 1, -13, 3, ..., -1, 15); 10 Hz, 0.2 degrees (18 kHz firings, 288 k pulses/s).
[[nodiscard]] RotatingScannerConfig vlp16();
/// Velodyne HDL-32E like: 32 beams from -30.67 to +10.67 degrees evenly (4/3 degree steps,
/// lowest first); 10 Hz, 0.16 degrees (22.5 kHz firings, 720 k pulses/s).
[[nodiscard]] RotatingScannerConfig hdl32();
/// Velodyne HDL-64E like: 64 beams from -24.9 to +2 degrees evenly (the real head's two blocks
/// have uneven spacing), lowest first; 10 Hz, 0.18 degrees (20 kHz firings, 1.28 M pulses/s).
[[nodiscard]] RotatingScannerConfig hdl64();
/// Ouster OS-128 like: 128 beams from -22.5 to +22.5 degrees evenly, lowest first; 10 Hz with
/// 1024 columns per revolution (0.3515625 degrees, 10.24 kHz firings, 1.31 M pulses/s).
[[nodiscard]] RotatingScannerConfig os128();

class RotatingScanner final : public ScanPattern {
  public:
    using Config = RotatingScannerConfig;

    /// Throws ConfigError listing every problem of `config`.
    explicit RotatingScanner(RotatingScannerConfig config);

    [[nodiscard]] std::uint64_t pulse_count() const override { return pulse_count_; }
    [[nodiscard]] double pulse_rate_hz() const override { return pulse_rate_hz_; }
    [[nodiscard]] double start_time_s() const override { return config_.start_time_s; }
    [[nodiscard]] const RotatingScannerConfig& config() const { return config_; }
    [[nodiscard]] std::size_t beam_count() const { return config_.beam_elevations_deg.size(); }

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;

    RotatingScannerConfig config_;
    std::uint64_t pulse_count_ = 0;
    double pulse_rate_hz_ = 0.0;
    /// 360 / azimuth resolution when that is a whole number (the azimuth is then computed
    /// from the firing index modulo a revolution, exactly periodic); 0 otherwise.
    std::uint64_t firings_per_revolution_ = 0;
    std::vector<double> cos_elevation_, sin_elevation_;
    /// cos/sin of each beam's azimuth within a firing (its share of the step plus its offset):
    /// a pulse's azimuth is the firing's heading plus this, so one sincos per firing suffices.
    std::vector<double> cos_beam_azimuth_, sin_beam_azimuth_;
};

}  // namespace beamtrace
