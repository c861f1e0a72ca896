// A rotating polygon mirror scanner (RIEGL VUX-1 / Q-series style): a mirror wheel of `facets`
// faces spins at rotation_rate_hz; each facet sweeps the beam once, in the same direction, so the
// scan is a sawtooth with a line rate of facets x rotation_rate_hz.
//
// Conventions (sensor frame: x forward/optical axis, y left, z up):
// - A facet turning by 360 / facets deg deflects the beam by twice that; only the centred
//   usable_fraction u of each facet sweep fires (near a facet's edges the beam is clipped). The
//   scan angle thus runs over [-A, A) with A = (360 / facets) u deg: s = -A + 2 A frac(lines),
//   lines = i x line_rate_hz / pulse_rate_hz (pulse i; line n = floor(lines)). The direction
//   is [cos s, sin s, 0] (the line scanner's: about +z, positive towards +y), scan_angle_deg =
//   s. Mount it as the line scanner ([0, -pi/2, 0]) for lines across track.
// - pulse_rate_hz is the rate of FIRED pulses (a data sheet's effective measurement rate), and
//   pulse i fires at t_i = start_time_s + i / pulse_rate_hz (the ScanPattern contract): the
//   fired pulses of a line are spread evenly over the line's whole period 1 / line_rate_hz, so
//   the mirror's dead time at the facet edges is folded into the line. A pulse's time is off
//   its physical emission time by at most (1 - u) / (2 line_rate_hz); the line rate, the points
//   per line and the scan angles are exact.
// - channel = the facet of the pulse's line, line n mod facets (written as LAS user data).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace {

struct PolygonScannerConfig {
    double pulse_rate_hz = 300'000.0;  ///< fired pulses per second
    int facets = 4;                    ///< mirror faces, in [2, 360]
    double rotation_rate_hz = 25.0;    ///< wheel revolutions per second (100 lines/s)
    double usable_fraction = 0.5;      ///< centred part of each facet sweep that fires, (0, 1]
    double duration_s = 1.0;           ///< survey length; whole pulses only
    double start_time_s = 0.0;         ///< time of pulse 0 and of line 0's start

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

class PolygonScanner final : public ScanPattern {
  public:
    using Config = PolygonScannerConfig;

    /// Throws ConfigError listing every problem of `config`.
    explicit PolygonScanner(PolygonScannerConfig config);

    [[nodiscard]] std::uint64_t pulse_count() const override { return pulse_count_; }
    [[nodiscard]] double pulse_rate_hz() const override { return config_.pulse_rate_hz; }
    [[nodiscard]] double start_time_s() const override { return config_.start_time_s; }
    [[nodiscard]] const PolygonScannerConfig& config() const { return config_; }

    /// Scan lines per second: facets x rotation_rate_hz.
    [[nodiscard]] double line_rate_hz() const;
    /// A = (360 / facets) x usable_fraction: the scan angle runs over [-A, A).
    [[nodiscard]] double scan_angle_max_deg() const;
    /// The scan line that pulse i belongs to.
    [[nodiscard]] std::uint64_t line_of_pulse(std::uint64_t i) const;

  private:
    void generate_pulses(std::uint64_t first, std::size_t count, PulseBatch& out) const override;

    PolygonScannerConfig config_;
    std::uint64_t pulse_count_ = 0;
};

}  // namespace beamtrace
