#include "beamtrace/sensor/mechanism_presets.hpp"

#include <array>

namespace beamtrace {
namespace {

// Livox's Risley prisms (modelling choices, docs/sensors.md): the rotor speeds HELIOS++ ships for
// its Livox scanners (scanners_als.xml, livox_mid-70: 121.567 and -77.733 revolutions per second,
// once written 7294 and -4664 per minute); the prisms' glass index is not published (a crown
// glass is assumed) and the wedge follows from the data sheet's field of view: 4 (n - 1) alpha =
// FOV.
constexpr double kLivoxRate1Hz = 7294.0 / 60.0;
constexpr double kLivoxRate2Hz = -4664.0 / 60.0;
constexpr double kLivoxIndex = 1.509;

RisleyScannerConfig livox(double fov_deg, double points_per_s) {
    RisleyScannerConfig c;
    c.pulse_rate_hz = points_per_s;
    c.refractive_index = kLivoxIndex;
    c.wedge_deg = fov_deg / 4.0 / (kLivoxIndex - 1.0);
    c.rotation_rate_1_hz = kLivoxRate1Hz;
    c.rotation_rate_2_hz = kLivoxRate2Hz;
    return c;
}

// Livox beams are elliptic, 0.28 x 0.03 deg (the data sheets do not say at which intensity level):
// a modelling choice takes the larger axis as the full 1/e^2 angle (docs/sensors.md).
constexpr double kLivoxDivergenceMrad = 0.28 * 3.14159265358979323846 / 180.0 * 1000.0;

constexpr std::string_view kMid40Source =
    "Livox Mid Series User Manual v1.0 (2019.01), Specifications; rotor speeds: HELIOS++";
constexpr std::string_view kAviaSource =
    "Livox Avia User Manual v1.0 (2020.10), Specifications; rotor speeds: HELIOS++";
constexpr std::string_view kVux1Source = "RIEGL VUX-1UAV data sheet (2015-2017 editions)";
constexpr std::string_view kVq880Source =
    "RIEGL VQ-880-G II green (circular scan) channel as in HELIOS++ scanners_als.xml "
    "(riegl_vq-880g)";
constexpr std::string_view kVq840Source =
    "RIEGL VQ-840-GL data sheet (VQ-840-G family), Technical Data: PRR, scan, wavelength, range";
constexpr std::string_view kAls50Source =
    "Leica ALS50-II product specifications; HELIOS++ data/scanners_als.xml (leica_als50-ii)";

const std::array<MechanismPreset<RisleyScannerConfig>, 2> kRisley{{
    {"livox_mid40", livox_mid40, {"Livox Mid-40", kMid40Source, 0, 260, kLivoxDivergenceMrad, 905}},
    {"livox_avia", livox_avia, {"Livox Avia", kAviaSource, 0, 450, kLivoxDivergenceMrad, 905}},
}};
const std::array<MechanismPreset<PolygonScannerConfig>, 1> kPolygon{{
    {"riegl_vux1uav", riegl_vux1uav, {"RIEGL VUX-1UAV", kVux1Source, 3, 920, 0.5, 0}},
}};
const std::array<MechanismPreset<ConicScannerConfig>, 2> kConic{{
    {"riegl_vq880g", riegl_vq880g, {"RIEGL VQ-880-G (green)", kVq880Source, 10, 0, 0.7, 532}},
    {"riegl_vq840g", riegl_vq840g, {"RIEGL VQ-840-G(L)", kVq840Source, 20, 0, 1.0, 532}},
}};
const std::array<MechanismPreset<LineScannerConfig>, 1> kLine{{
    {"leica_als50_ii", leica_als50_ii, {"Leica ALS50-II", kAls50Source, 200, 6000, 0.22, 1064}},
}};

}  // namespace

RisleyScannerConfig livox_mid40() {
    return livox(38.4, 100'000.0);
}

RisleyScannerConfig livox_avia() {
    return livox(70.4, 240'000.0);
}

PolygonScannerConfig riegl_vux1uav() {
    PolygonScannerConfig c;
    c.pulse_rate_hz = 500'000.0;      // effective measurement rate (550 kHz PRR x 330/360)
    c.facets = 2;                     // one 45 deg mirror: a line per revolution, 360 deg each
    c.rotation_rate_hz = 100.0;       // 200 lines/s (the data sheet's 200 revolutions/s)
    c.usable_fraction = 330.0 / 360;  // the 330 deg field of view
    return c;
}

ConicScannerConfig riegl_vq880g() {
    ConicScannerConfig c;
    c.pulse_rate_hz = 700'000.0;  // the green channel's highest (200/400/550/700 kHz)
    c.rotation_rate_hz = 80.0;    // its highest scan rate (30-80 Hz)
    c.off_axis_deg = 20.0;        // 40 deg circular field of view
    return c;
}

ConicScannerConfig riegl_vq840g() {
    ConicScannerConfig c;
    c.pulse_rate_hz = 200'000.0;  // PRR 50-200 kHz
    c.rotation_rate_hz = 100.0;   // 10-100 lines/s, one line per mirror revolution
    c.off_axis_deg = 20.0;        // +/-20 deg across track (the +/-14 deg along track is not drawn)
    return c;
}

LineScannerConfig leica_als50_ii() {
    LineScannerConfig c;
    c.pulse_rate_hz = 150'000.0;
    c.scan_rate_hz = 90.0;  // mirror periods per second: 180 lines/s
    c.scan_angle_max_deg = 37.5;
    c.waveform = ScanWaveform::triangle;
    return c;
}

std::span<const MechanismPreset<RisleyScannerConfig>> risley_presets() {
    return kRisley;
}

std::span<const MechanismPreset<PolygonScannerConfig>> polygon_presets() {
    return kPolygon;
}

std::span<const MechanismPreset<ConicScannerConfig>> conic_presets() {
    return kConic;
}

std::span<const MechanismPreset<LineScannerConfig>> line_presets() {
    return kLine;
}

}  // namespace beamtrace
