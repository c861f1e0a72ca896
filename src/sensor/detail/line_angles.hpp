// A line scanner's pulse times and mirror angles (sawtooth and triangle without turns), one
// pulse at a time or four in AVX2 lanes with the same operations, so the same bits.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace beamtrace::detail {

/// What a line scanner's angle of pulse i depends on.
struct LineAngleParams {
    double start_s = 0.0;        ///< the time of pulse 0
    double pulse_rate_hz = 1.0;  ///< pulses per second
    double lines_per_s = 1.0;    ///< scan lines per second
    double max_deg = 1.0;        ///< the scan angle's amplitude
    bool triangle = false;       ///< triangle (no turns); else sawtooth
};

/// The fractional part of x, in [0, 1) for x >= 0: x - floor(x) alone, the lanes' operations
/// (detail::frac also maps the 1 that a tiny negative x rounds to back to 0; a line scanner's
/// mirror angles keep the expression they always had).
[[nodiscard]] inline double line_frac(double x) {
    return x - std::floor(x);
}

/// The sawtooth's angle at `lines`, degrees.
[[nodiscard]] inline double sawtooth_deg(double max_deg, double lines) {
    return -max_deg + 2.0 * max_deg * line_frac(lines);
}

/// The triangle's angle (no turns) at `lines`, degrees.
[[nodiscard]] inline double triangle_deg(double max_deg, double lines) {
    return max_deg * (1.0 - 4.0 * std::abs(line_frac(0.5 * lines) - 0.5));
}

/// Pulse i's lines: i x lines/s / pulse rate (the expression of LineScanner::line_of_pulse).
[[nodiscard]] inline double lines_of_pulse(const LineAngleParams& p, std::uint64_t i) {
    return static_cast<double>(i) * p.lines_per_s / p.pulse_rate_hz;
}

/// Pulses [first, first + count): their angles (degrees) into angle_deg[j] and times into
/// time_s[j], one pulse at a time.
void line_angles_scalar(const LineAngleParams& p, std::uint64_t first, std::size_t count,
                        double* angle_deg, double* time_s);

/// line_angles_scalar() four pulses at a time in AVX2 lanes while four are left, when the CPU
/// has AVX2 and first + count < 2^52; returns how many pulses it did (a multiple of 4, 0
/// without AVX2): the same bits.
[[nodiscard]] std::size_t line_angles_lanes(const LineAngleParams& p, std::uint64_t first,
                                            std::size_t count, double* angle_deg, double* time_s);

}  // namespace beamtrace::detail
