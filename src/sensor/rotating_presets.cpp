#include "beamtrace/sensor/rotating_presets.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace beamtrace {
namespace {

/// A clockwise 10 Hz head with the given rows (firing order), one revolution long.
RotatingScannerConfig table_preset(std::vector<double> elevations_deg) {
    RotatingScannerConfig c;
    c.beam_elevations_deg = std::move(elevations_deg);
    c.rotation_rate_hz = 10.0;
    c.spin_clockwise = true;
    c.duration_s = 0.1;
    return c;
}

/// `n` times `step_s` apart from 0.
std::vector<double> every(std::size_t n, double step_s) {
    std::vector<double> t(n);
    for (std::size_t b = 0; b < n; ++b) {
        t[b] = static_cast<double>(b) * step_s;
    }
    return t;
}

// Ouster SDK, ouster_client types.cpp, gen1_altitude_angles (design values for OS1-64).
constexpr std::array<double, 64> kOs1_64AltitudeDeg{
    16.611,  16.084,  15.557,  15.029,  14.502,  13.975,  13.447,  12.920,  12.393,  11.865,
    11.338,  10.811,  10.283,  9.756,   9.229,   8.701,   8.174,   7.646,   7.119,   6.592,
    6.064,   5.537,   5.010,   4.482,   3.955,   3.428,   2.900,   2.373,   1.846,   1.318,
    0.791,   0.264,   -0.264,  -0.791,  -1.318,  -1.846,  -2.373,  -2.900,  -3.428,  -3.955,
    -4.482,  -5.010,  -5.537,  -6.064,  -6.592,  -7.119,  -7.646,  -8.174,  -8.701,  -9.229,
    -9.756,  -10.283, -10.811, -11.338, -11.865, -12.393, -12.920, -13.447, -13.975, -14.502,
    -15.029, -15.557, -16.084, -16.611};
// gen1_azimuth_angles: the same four values repeated, by row modulo 4.
constexpr std::array<double, 4> kOs1_64AzimuthDeg{3.164, 1.055, -1.055, -3.164};

constexpr double kUs = 1e-6;

// OS1 data sheet (Gen1): 0.8 m - 120 m at 80 % reflectivity, for the 16, 64 and 128 beam units.
constexpr double kOs1RangeMinM = 0.8;
constexpr double kOs1RangeMaxM = 120.0;

}  // namespace

RotatingScannerConfig velodyne_vlp16() {
    RotatingScannerConfig c =
        table_preset({-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15});
    c.firing_period_s = 55.296 * kUs;
    c.beam_time_offsets_s = every(16, 2.304 * kUs);
    c.preset_range_max_m = 100.0;
    return c;
}

RotatingScannerConfig velodyne_hdl32e() {
    RotatingScannerConfig c = table_preset(
        {-30.67, -9.33,  -29.33, -8.00,  -28.00, -6.67,  -26.67, -5.33,  -25.33, -4.00,  -24.00,
         -2.67,  -22.67, -1.33,  -21.33, 0.00,   -20.00, 1.33,   -18.67, 2.67,   -17.33, 4.00,
         -16.00, 5.33,   -14.67, 6.67,   -13.33, 8.00,   -12.00, 9.33,   -10.67, 10.67});
    c.firing_period_s = 46.08 * kUs;
    c.beam_time_offsets_s = every(32, 1.152 * kUs);
    c.preset_range_min_m = 0.05;  // the manual's valid data range, 5 cm to 100 m
    c.preset_range_max_m = 100.0;
    return c;
}

RotatingScannerConfig velodyne_hdl64e() {
    // Rows in firing order: upper laser u (channel u) and lower laser u (channel 32 + u) fire
    // together (the S2 manual's transmit timing table); the 50 us cycle, 1/32 of it between
    // pairs (20 kHz firings, 1.28 M points/s at 0.18 deg), is a modelling choice.
    RotatingScannerConfig c = table_preset({});
    constexpr double kPeriodS = 50.0 * kUs;
    for (std::uint16_t u = 0; u < 32; ++u) {
        const double t = static_cast<double>(u) * kPeriodS / 32.0;
        c.beam_elevations_deg.push_back(2.0 - static_cast<double>(u) / 3.0);
        c.beam_channels.push_back(u);
        c.beam_time_offsets_s.push_back(t);
        c.beam_elevations_deg.push_back(-8.83 - static_cast<double>(u) / 2.0);
        c.beam_channels.push_back(static_cast<std::uint16_t>(32 + u));
        c.beam_time_offsets_s.push_back(t);
    }
    c.firing_period_s = kPeriodS;
    c.preset_range_max_m = 120.0;
    return c;
}

RotatingScannerConfig ouster_os1_64() {
    RotatingScannerConfig c =
        table_preset(std::vector<double>(kOs1_64AltitudeDeg.begin(), kOs1_64AltitudeDeg.end()));
    for (std::size_t b = 0; b < 64; ++b) {
        c.beam_azimuth_offsets_deg.push_back(-kOs1_64AzimuthDeg[b % 4]);
    }
    c.azimuth_resolution_deg = 360.0 / 1024.0;
    c.beam_time_offsets_s.assign(64, 0.0);
    c.preset_range_min_m = kOs1RangeMinM;
    c.preset_range_max_m = kOs1RangeMaxM;
    return c;
}

RotatingScannerConfig ouster_os1_128() {
    std::vector<double> e(128);
    for (std::size_t b = 0; b < 128; ++b) {
        e[b] = b == 127 ? -22.5 : 22.5 - 45.0 * static_cast<double>(b) / 127.0;
    }
    RotatingScannerConfig c = table_preset(std::move(e));
    c.azimuth_resolution_deg = 360.0 / 1024.0;
    c.beam_time_offsets_s.assign(128, 0.0);
    c.preset_range_min_m = kOs1RangeMinM;
    c.preset_range_max_m = kOs1RangeMaxM;
    return c;
}

namespace {

constexpr std::string_view kVlp16Manual = "VLP-16 User Manual, 63-9243 Rev D";
constexpr std::string_view kHdl32Manual = "HDL-32E User's Manual (Velodyne LiDAR)";
constexpr std::string_view kHdl64Manual =
    "HDL-64E S2 manual Appendix G (paired firing), S3 manual 63-HDL64ES3 Rev K; nominal layout";
constexpr std::string_view kOusterSdk =
    "Ouster SDK ouster_client gen1 design values; OS1 (Gen1) data sheet";
constexpr std::string_view kOs1Sheet = "OS1 (Gen1) data sheet: 45 deg vertical field of view";

const std::array<RotatingPreset, 9> kPresets{{
    {"vlp16", vlp16, {"VLP-16 like (simplified)", "beamtrace", 0, 0}},
    {"hdl32", hdl32, {"HDL-32E like (simplified)", "beamtrace", 0, 0}},
    {"hdl64", hdl64, {"HDL-64E like (simplified)", "beamtrace", 0, 0}},
    {"os128", os128, {"OS-128 like (simplified)", "beamtrace", 0, 0}},
    {"velodyne_vlp16", velodyne_vlp16, {"Velodyne VLP-16", kVlp16Manual, 903e-9, 300e3}},
    {"velodyne_hdl32e", velodyne_hdl32e, {"Velodyne HDL-32E", kHdl32Manual, 903e-9, 700e3}},
    {"velodyne_hdl64e", velodyne_hdl64e, {"Velodyne HDL-64E S2/S3", kHdl64Manual, 905e-9, 1.3e6}},
    {"ouster_os1_64", ouster_os1_64, {"Ouster OS1-64", kOusterSdk, 850e-9, 1310720}},
    {"ouster_os1_128", ouster_os1_128, {"Ouster OS1-128", kOs1Sheet, 850e-9, 2621440}},
}};

}  // namespace

std::span<const RotatingPreset> rotating_presets() {
    return kPresets;
}

const RotatingPreset* find_rotating_preset(std::string_view name) {
    const auto* it = std::find_if(kPresets.begin(), kPresets.end(),
                                  [&](const RotatingPreset& p) { return p.name == name; });
    return it != kPresets.end() ? &*it : nullptr;
}

std::string rotating_preset_names() {
    std::string s;
    for (const auto& p : kPresets) {
        s += (s.empty() ? "" : ", ") + std::string(p.name);
    }
    return s;
}

}  // namespace beamtrace
