// The registry entries of the scan pattern types, one function per type in the type's own file
// (scan_pattern_registry.hpp says how to add one), and what the single-beam mechanisms (conic,
// polygon, risley, fibre) share: their pulse timing keys and its checks.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "beamtrace/sensor/scan_pattern.hpp"
#include "beamtrace/sensor/scan_pattern_registry.hpp"
#include "sensor/detail/scanner_yaml.hpp"

namespace beamtrace::detail {

[[nodiscard]] ScanPatternEntry rotating_scanner_entry();  // rotating_scanner.cpp
[[nodiscard]] ScanPatternEntry line_scanner_entry();      // line_scanner.cpp
[[nodiscard]] ScanPatternEntry conic_scanner_entry();     // conic_scanner.cpp
[[nodiscard]] ScanPatternEntry polygon_scanner_entry();   // polygon_scanner.cpp
[[nodiscard]] ScanPatternEntry risley_scanner_entry();    // risley_scanner.cpp
[[nodiscard]] ScanPatternEntry fibre_scanner_entry();     // fibre_scanner.cpp
[[nodiscard]] ScanPatternEntry pinhole_pattern_entry();   // image_pattern.cpp
[[nodiscard]] ScanPatternEntry scan_pattern_entry();      // image_pattern.cpp
[[nodiscard]] ScanPatternEntry rays_file_entry();         // rays_file.cpp

/// The problems of a mechanism's pulse timing (the line scanner's rules): a positive finite
/// pulse rate, a positive duration of at least one and below 9e15 pulses, a finite start time.
inline void pulse_timing_problems(double pulse_rate_hz, double duration_s, double start_time_s,
                                  std::vector<std::string>& p) {
    const bool rate_ok = pulse_rate_hz > 0.0 && std::isfinite(pulse_rate_hz);
    if (!rate_ok) {
        p.push_back("pulse_rate_hz must be positive (got " + std::to_string(pulse_rate_hz) + ")");
    }
    if (!(duration_s > 0.0 && std::isfinite(duration_s))) {
        p.push_back("duration_s must be positive (got " + std::to_string(duration_s) + ")");
    } else if (rate_ok) {
        const double pulses = duration_s * pulse_rate_hz;
        if (!(pulses <= 9.0e15)) {
            p.push_back("duration_s x pulse_rate_hz must be below 9e15 pulses");
        } else if (whole_count(pulses) == 0) {
            p.push_back("duration_s (" + std::to_string(duration_s) +
                        ") is shorter than one pulse");
        }
    }
    if (!std::isfinite(start_time_s)) {
        p.push_back("start_time_s must be finite");
    }
}

/// Reads `pulse_rate_hz` (positive) and `duration_s` (any number: validate() judges it) of a
/// mechanism's `scanner:` block, when present.
inline void parse_pulse_timing(YamlChecker& c, const YAML::Node& n, double& pulse_rate_hz,
                               double& duration_s) {
    scanner_positive(c, n, "pulse_rate_hz", pulse_rate_hz);
    double d = 0.0;
    if (n["duration_s"] && c.number(n["duration_s"], "scanner.duration_s", d)) {
        duration_s = d;
    }
}

/// The fractional part of x, in [0, 1) (x - floor(x); 0 for an integer).
[[nodiscard]] inline double frac(double x) {
    const double f = x - std::floor(x);
    return f < 1.0 ? f : 0.0;
}

}  // namespace beamtrace::detail
