// A spinning multi-beam LiDAR (Velodyne, Ouster, Hesai style).
//
// Conventions (sensor frame: x forward, y left, z up):
// - The head spins about the sensor z axis. Azimuth 0 is the sensor +x axis and azimuth grows
//   towards +y (counter-clockwise seen from above); with `spin_clockwise` the head turns the
//   other way (azimuth decreasing over time), as real Velodyne and Ouster heads do.
// - Beam b has elevation beam_elevations_deg[b] (positive up) and fires with channel = b.
//   Its direction at azimuth a is [cos e cos a, cos e sin a, sin e], the report's scan formula.
// - Pulse i is beam row b = i % beams of firing k = i / beams; rows are in FIRING order and
//   row b fires with channel beam_channels[b] (default b). Without a timing table the beams are
//   STAGGERED evenly: t_i = start_time_s + i / pulse_rate_hz. With beam_time_offsets_s (a data
//   sheet's firing sequence, e.g. the VLP-16's 2.304 us steps and 18.43 us recharge) row b
//   fires at t = start_time_s + k * firing period + beam_time_offsets_s[b]. Either way the
//   azimuth is the head's angle at that time plus the row's azimuth offset: a_i =
//   start_azimuth_deg +/- (k * step + rotation during the firing up to t) +
//   beam_azimuth_offsets_deg[b]. So each beam steps by exactly one azimuth step per firing and
//   the head's rotation during a firing is modelled.
// - Azimuth step = azimuth_resolution_deg, or rotation_rate_hz * 360 * firing_period_s when a
//   firing period is set (Velodyne heads fire on a fixed clock, so their step grows with the
//   rotation rate). Firing rate = rotation_rate_hz * 360 / step; pulse rate = beams x firing
//   rate; firings per revolution = 360 / step.
// - scan_angle_deg = the pulse's azimuth a_i wrapped into [-180, 180).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

struct RotatingScannerConfig {
    /// Elevation of each beam in degrees (positive up), in channel order; in [-90, 90].
    std::vector<double> beam_elevations_deg;
    /// Azimuth offset of each beam in degrees, positive counter-clockwise seen from above (empty:
    /// all 0; else one per beam). NOTE: Ouster's beam_azimuth_angles count the other way.
    std::vector<double> beam_azimuth_offsets_deg;
    /// Time of each beam's pulse after its firing starts, in seconds (empty: staggered evenly;
    /// else one per beam, non-decreasing, in [0, firing period)).
    std::vector<double> beam_time_offsets_s;
    /// Channel (laser ID) of each beam row (empty: the row index; else one per beam, distinct).
    std::vector<std::uint16_t> beam_channels;
    double rotation_rate_hz = 10.0;       ///< revolutions per second
    double azimuth_resolution_deg = 0.2;  ///< head rotation between firings, (0, 360]
    /// Firing cycle in seconds; 0: none (the step is azimuth_resolution_deg). When positive the
    /// step is rotation_rate_hz * 360 * firing_period_s and azimuth_resolution_deg is unused.
    double firing_period_s = 0.0;
    double start_azimuth_deg = 0.0;  ///< head azimuth at start_time_s
    bool spin_clockwise = false;     ///< false: azimuth grows towards +y over time
    double duration_s = 0.1;         ///< survey length; whole firings only
    double start_time_s = 0.0;       ///< time of pulse 0
    /// The range limits of the sensor's data sheet, in metres (0: not given), set by the
    /// data-sheet presets: a survey's range_min_m / range_max_m default to them.
    double preset_range_min_m = 0.0;
    double preset_range_max_m = 0.0;

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;

    /// The head's rotation between firings in degrees (see firing_period_s).
    [[nodiscard]] double azimuth_step_deg() const {
        return firing_period_s > 0.0 ? rotation_rate_hz * 360.0 * firing_period_s
                                     : azimuth_resolution_deg;
    }
    [[nodiscard]] double firing_rate_hz() const {
        return firing_period_s > 0.0 ? 1.0 / firing_period_s
                                     : rotation_rate_hz * 360.0 / azimuth_resolution_deg;
    }
    [[nodiscard]] double pulse_rate_hz() const {
        return static_cast<double>(beam_elevations_deg.size()) * firing_rate_hz();
    }
    /// {preset_range_min_m, preset_range_max_m} when a preset gives a maximum range.
    [[nodiscard]] std::optional<std::pair<double, double>> preset_range_m() const {
        if (!(preset_range_max_m > 0.0)) {
            return std::nullopt;
        }
        return std::pair{preset_range_min_m, preset_range_max_m};
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
    /// Pulse i's emission time as generate() gives it: with a timing table (beam time offsets)
    /// its firing's start plus its row's offset; else (and for i >= pulse_count()) the uniform
    /// start + i / rate.
    [[nodiscard]] double pulse_time_s(std::uint64_t i) const override;
    [[nodiscard]] const RotatingScannerConfig& config() const { return config_; }
    [[nodiscard]] std::size_t beam_count() const { return config_.beam_elevations_deg.size(); }

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;
    /// The emission time of pulse i, row b of firing `firing`.
    [[nodiscard]] double beam_time_s(std::uint64_t i, std::uint64_t firing, std::size_t b) const;

    RotatingScannerConfig config_;
    std::uint64_t pulse_count_ = 0;
    double pulse_rate_hz_ = 0.0;
    /// 360 / azimuth resolution when that is a whole number (the azimuth is then computed
    /// from the firing index modulo a revolution, exactly periodic); 0 otherwise.
    std::uint64_t firings_per_revolution_ = 0;
    std::vector<double> cos_elevation_, sin_elevation_;
    double step_deg_ = 0.0;  ///< config_.azimuth_step_deg()
    double period_s_ = 0.0;  ///< the firing cycle, 1 / firing rate
    /// Each beam's head rotation within its firing (its share of the step), degrees.
    std::vector<double> within_deg_;
    /// cos/sin of each beam's azimuth within a firing (its share of the step plus its offset):
    /// a pulse's azimuth is the firing's heading plus this, so one sincos per firing suffices.
    std::vector<double> cos_beam_azimuth_, sin_beam_azimuth_;
};

}  // namespace beamtrace
