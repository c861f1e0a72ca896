// Presets of the rotating scanner: real spinning sensors with their per-beam tables (elevation,
// azimuth offset, firing order and timing) and the facts their data sheets give. Every value
// and its source is listed in docs/sensors.md.
//
// Two families:
// - the data-sheet presets (velodyne_vlp16, velodyne_hdl32e, velodyne_hdl64e, ouster_os1_64,
//   ouster_os1_128): rows in firing order, the documented timing, clockwise spin;
// - the older simplified presets (vlp16, hdl32, hdl64, os128; rotating_scanner.hpp): evenly
//   staggered beams, counter-clockwise, kept unchanged so that existing surveys give the same
//   points.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "beamtrace/sensor/rotating_scanner.hpp"

namespace beamtrace {

/// What a sensor's data sheet says beyond its beam table and range limits (those are in the
/// config: preset_range_min_m / preset_range_max_m); 0: not given there.
struct RotatingSensorFacts {
    std::string_view model;   ///< e.g. "Velodyne VLP-16"
    std::string_view source;  ///< document title and revision (docs/sensors.md)
    double wavelength_m = 0.0;
    /// single return, as the data sheet rounds it: its highest mode (a preset may run a lower one)
    double nominal_points_per_s = 0.0;
};

struct RotatingPreset {
    std::string_view name;
    RotatingScannerConfig (*make)();
    RotatingSensorFacts facts;
};

/// Velodyne VLP-16 (VLP-16 User Manual 63-9243 Rev D): laser IDs 0-15 in firing order, 2.304 us
/// apart in a 55.296 us cycle; 10 Hz; clockwise.
[[nodiscard]] RotatingScannerConfig velodyne_vlp16();
/// Velodyne HDL-32E (HDL-32E User's Manual): laser IDs 0-31 in firing order (elevations
/// interleaved), 1.152 us apart in a 46.08 us cycle; 10 Hz; clockwise.
[[nodiscard]] RotatingScannerConfig velodyne_hdl32e();
/// Velodyne HDL-64E S2/S3 nominal layout (its calibration is unit-specific; docs/sensors.md):
/// upper block +2 to -8.33 deg in 1/3 deg steps, lower block -8.83 to -24.33 deg in 1/2 deg
/// steps, one laser of each block firing together; 10 Hz, 0.18 deg; clockwise.
[[nodiscard]] RotatingScannerConfig velodyne_hdl64e();
/// Ouster OS1-64 (Gen1 design values of the Ouster SDK): beam_altitude_angles from +16.611 to
/// -16.611 deg, beam_azimuth_angles +/-3.164 and +/-1.055 deg (negated: see
/// beam_azimuth_offsets_deg); 1024 columns at 10 Hz, a column's beams fire together; range
/// 0.8-120 m (OS1 data sheet); clockwise.
[[nodiscard]] RotatingScannerConfig ouster_os1_64();
/// Ouster OS1-128 (data sheet: 45 deg vertical field of view; uniform spacing is a modelling
/// choice): +22.5 to -22.5 deg, azimuth offsets 0 (unit-specific, not in the data sheet); 1024 x
/// 10; range 0.8-120 m; clockwise.
[[nodiscard]] RotatingScannerConfig ouster_os1_128();

/// Every preset of the rotating scanner, the simplified ones first.
[[nodiscard]] std::span<const RotatingPreset> rotating_presets();
/// The preset named `name`, or nullptr.
[[nodiscard]] const RotatingPreset* find_rotating_preset(std::string_view name);
/// "vlp16, hdl32, ..., ouster_os1_128": the preset names, for messages.
[[nodiscard]] std::string rotating_preset_names();

}  // namespace beamtrace
