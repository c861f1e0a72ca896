// A spinning multi-beam scanner's pulses within one firing, four beams at a time in AVX2 lanes
// with the scalar path's operations in its order (so its bits): RotatingScanner::generate_pulses.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "beamtrace/sensor/scan_pattern.hpp"

namespace beamtrace::detail {

/// What the pulses of one firing depend on (uniform times: start + i / rate).
struct FiringParams {
    double start_azimuth_deg = 0.0;
    double sign = 1.0;      ///< -1 clockwise
    double head_deg = 0.0;  ///< the firing's head rotation
    double cos_head = 1.0, sin_head = 0.0;
    double start_s = 0.0, pulse_rate_hz = 1.0;
    /// Per beam: its rotation within the firing and azimuth offset (degrees), cos/sin of its
    /// azimuth within the firing and of its elevation; its channel (nullptr: the beam index).
    const double *within_deg = nullptr, *offset_deg = nullptr;
    const double *cos_beam = nullptr, *sin_beam = nullptr;
    const double *cos_elevation = nullptr, *sin_elevation = nullptr;
    const std::uint16_t* channels = nullptr;
};

/// `deg` wrapped into [-180, 180).
[[nodiscard]] inline double wrap_deg(double deg) {
    double w = deg + 180.0;
    if (w >= 360.0 && w < 720.0) {
        // fmod(w, 360) is w - 360 here, and that difference is exact (Sterbenz: w <= 2 x 360):
        // a spinning head's azimuths past 180 degrees take this path, not fmod.
        w -= 360.0;
    } else if (!(w >= 0.0 && w < 360.0)) {  // fmod only when needed (the same value otherwise)
        w = std::fmod(w, 360.0);
        if (w < 0.0) {
            w += 360.0;
        }
    }
    return w - 180.0;
}

/// Pulse `pulse`, beam `b` of the firing `f`, emitted at `time_s`, into slot j of `out`.
inline void firing_pulse(const FiringParams& f, double time_s, std::size_t b, PulseBatch& out,
                         std::size_t j) {
    const double az_deg =
        wrap_deg(f.start_azimuth_deg + f.sign * (f.head_deg + f.within_deg[b]) + f.offset_deg[b]);
    const double cos_az = f.cos_head * f.cos_beam[b] - f.sin_head * f.sin_beam[b];
    const double sin_az = f.sin_head * f.cos_beam[b] + f.cos_head * f.sin_beam[b];
    out.time_s[j] = time_s;
    out.direction[j] = {f.cos_elevation[b] * cos_az, f.cos_elevation[b] * sin_az,
                        f.sin_elevation[b]};
    out.channel[j] = f.channels == nullptr ? static_cast<std::uint16_t>(b) : f.channels[b];
    out.scan_angle_deg[j] = static_cast<float>(az_deg);
}

/// firing_pulse() of pulses first .. first + count - 1 at uniform times (start_s + i /
/// pulse_rate_hz), beams b .. b + count - 1 of one firing, into slots j .. of `out`, four at a
/// time in AVX2 lanes: returns how many it did (a multiple of 4; 0 without AVX2). It stops
/// before a four whose azimuths need std::fmod to wrap.
[[nodiscard]] std::size_t firing_lanes(const FiringParams& f, std::uint64_t first, std::size_t b,
                                       std::size_t count, PulseBatch& out, std::size_t j);

}  // namespace beamtrace::detail
