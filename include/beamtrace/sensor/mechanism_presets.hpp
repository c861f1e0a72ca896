// Presets of the single-beam scan mechanisms: real airborne and solid-state sensors (Livox
// Mid-40 and Avia, RIEGL VUX-1UAV, VQ-880-G and VQ-840-G, Leica ALS50-II) as a mechanism config
// plus the facts of their data sheets. Every value and its source is listed in docs/sensors.md.
//
// A survey's `scanner: {type: risley, preset: livox_mid40, ...}` starts from the preset's
// config; every other key of the block overrides the preset's value. The data sheet's range
// limits become the survey's defaults for range_min_m / range_max_m, and its beam divergence and
// wavelength the defaults of physics.beam.divergence_mrad and physics.wavelength_nm (when the
// survey has a physics block); keys given in the survey file win.
//
// A preset sets the HIGHEST pulse and scan rates its data sheet lists (a mission usually flies
// lower ones: set pulse_rate_hz / scan_rate_hz / rotation_rate_hz) and leaves duration_s at the
// mechanism's default.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "beamtrace/sensor/conic_scanner.hpp"
#include "beamtrace/sensor/line_scanner.hpp"
#include "beamtrace/sensor/polygon_scanner.hpp"
#include "beamtrace/sensor/risley_scanner.hpp"

namespace beamtrace {

/// What a data sheet says beyond the scan mechanism; 0: not given there.
struct SensorDataSheet {
    std::string_view model;   ///< e.g. "Livox Mid-40"
    std::string_view source;  ///< document title and revision (docs/sensors.md)
    double range_min_m = 0.0;
    double range_max_m = 0.0;      ///< 0: no maximum given (the survey's default stays)
    double divergence_mrad = 0.0;  ///< full angle at 1/e^2 (the larger axis of an elliptic beam)
    double wavelength_nm = 0.0;
};

/// A named preset of the mechanism whose config is `Config`.
template <class Config>
struct MechanismPreset {
    std::string_view name;
    Config (*make)();
    SensorDataSheet sheet;
};

/// Livox Mid-40: Risley prisms drawing a 38.4 deg circular field of view, 100 000 points/s.
[[nodiscard]] RisleyScannerConfig livox_mid40();
/// Livox Avia, non-repetitive mode as one Risley disc 70.4 deg across (the data sheet's
/// horizontal field of view; its 77.2 deg vertical extent is not drawn), 240 000 points/s.
[[nodiscard]] RisleyScannerConfig livox_avia();
/// RIEGL VUX-1UAV: a 330 deg sweep per mirror revolution, 200 lines/s, 500 000 measurements/s
/// (one rotating 45 deg mirror, modelled as 2 facets turning at half the line rate).
[[nodiscard]] PolygonScannerConfig riegl_vux1uav();
/// RIEGL VQ-880-G, green channel (as HELIOS++ ships it): a 40 deg circular conic scan (20 deg off
/// axis), 80 revolutions/s, 700 kHz, 532 nm.
[[nodiscard]] ConicScannerConfig riegl_vq880g();
/// RIEGL VQ-840-G(L) topo-bathymetric scanner: its nearly elliptic scan (+/-20 deg across, +/-14
/// deg along track) as a 20 deg conic scan, 100 revolutions (lines)/s, 200 kHz, 532 nm.
[[nodiscard]] ConicScannerConfig riegl_vq840g();
/// Leica ALS50-II: an oscillating mirror (triangle), +/-37.5 deg, 90 Hz mirror frequency (180
/// lines/s), 150 kHz.
[[nodiscard]] LineScannerConfig leica_als50_ii();

[[nodiscard]] std::span<const MechanismPreset<RisleyScannerConfig>> risley_presets();
[[nodiscard]] std::span<const MechanismPreset<PolygonScannerConfig>> polygon_presets();
[[nodiscard]] std::span<const MechanismPreset<ConicScannerConfig>> conic_presets();
[[nodiscard]] std::span<const MechanismPreset<LineScannerConfig>> line_presets();

/// The preset of `presets` named `name`, or nullptr.
template <class Config>
[[nodiscard]] const MechanismPreset<Config>* find_mechanism_preset(
    std::span<const MechanismPreset<Config>> presets, std::string_view name) {
    for (const auto& p : presets) {
        if (p.name == name) {
            return &p;
        }
    }
    return nullptr;
}

/// "livox_mid40 or livox_avia": the names of `presets`, for messages.
template <class Config>
[[nodiscard]] std::string mechanism_preset_names(std::span<const MechanismPreset<Config>> presets) {
    std::string s;
    for (std::size_t i = 0; i < presets.size(); ++i) {
        s += (i == 0 ? "" : (i + 1 == presets.size() ? " or " : ", ")) +
             std::string(presets[i].name);
    }
    return s;
}

}  // namespace beamtrace
