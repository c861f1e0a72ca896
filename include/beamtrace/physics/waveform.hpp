// The received waveform of one pulse and the echoes (returns) found in it.
//
// Every sub-ray echo j (one-way range R_j, peak received power P_j) adds a Gaussian pulse of the
// emitted shape at its round-trip time t_j = 2 R_j / c:
//   w(t) = sum_j P_j exp(-(t - t_j)^2 / (2 sigma^2)),  sigma = FWHM / (2 sqrt(2 ln 2)).
// w is sampled at t = k * bin_ns (absolute bins: sample k of the record is bin first_bin + k),
// over [min t_j - 5 sigma, max t_j + 5 sigma].
//
// Echo detection: every local maximum of the samples (w[k-1] < w[k] >= w[k+1]) is refined with
// a Gaussian through its three samples (a parabola through their logarithms: exact for an
// isolated echo), giving its time (-> range = c t / 2), amplitude A and width sigma_e; echoes
// with A below the detection threshold are dropped. Reported per echo: range, amplitude (peak
// power, W), echo width (FWHM of the fitted Gaussian, ns) and the equivalent power: the echo's
// energy (the samples summed between the valleys either side of the peak, times bin_ns)
// divided by the energy of a unit-peak emitted pulse (sigma sqrt(2 pi)). It equals the sum of
// the P_j that formed the echo even when a tilted or rough surface stretches or merges it
// (overlapping echoes split their energy at the valley between them).
// Resolution: two equal echoes merge into one peak when they are closer than 2 sigma in time,
// i.e. c sigma in range (0.85 FWHM x c / 2: 0.51 m for a 4 ns pulse); the merged echo lies
// between them and is wider.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace beamtrace {

inline constexpr double kSpeedOfLight_m_per_s = 299'792'458.0;

struct WaveformConfig {
    double pulse_fwhm_ns = 4.0;  ///< emitted pulse width (full width at half maximum)
    double bin_ns = 0.5;         ///< digitiser sample spacing, at most pulse_fwhm_ns / 2

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// One sub-ray's contribution: one-way range [m] and peak received power [W].
struct EchoContribution {
    double range_m = 0.0;
    double power_w = 0.0;
};

/// A sampled waveform: samples_w[k] is the received power at time (first_bin + k) * bin_ns.
struct Waveform {
    std::int64_t first_bin = 0;
    double bin_ns = 0.5;
    std::vector<double> samples_w;

    /// Round-trip time of sample k in ns.
    [[nodiscard]] double time_ns(std::size_t k) const {
        return static_cast<double>(first_bin + static_cast<std::int64_t>(k)) * bin_ns;
    }
};

struct Echo {
    double range_m = 0.0;      ///< one-way range of the peak
    double amplitude_w = 0.0;  ///< peak power of the fitted Gaussian
    double width_ns = 0.0;     ///< FWHM of the fitted Gaussian
    double power_w = 0.0;      ///< equivalent power: echo energy / (sigma sqrt(2 pi))
};

/// Nanoseconds of round trip per metre of one-way range (2 / c).
[[nodiscard]] constexpr double round_trip_ns_per_m() {
    return 2.0e9 / kSpeedOfLight_m_per_s;
}

/// Builds the waveform of the contributions (cleared first; empty when there are none).
void build_waveform(const WaveformConfig& config, std::span<const EchoContribution> contributions,
                    Waveform& out);

/// Appends the echoes of `waveform` with amplitude >= threshold_w to `out` in range order.
void detect_echoes(const WaveformConfig& config, const Waveform& waveform, double threshold_w,
                   std::vector<Echo>& out);

}  // namespace beamtrace
