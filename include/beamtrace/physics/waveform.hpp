// The received waveform of one pulse and the echoes (returns) found in it.
//
// Every sub-ray echo j (one-way range R_j, peak received power P_j, width sigma_j) adds a
// Gaussian at its round-trip time t_j = 2 R_j / c:
//   w(t) = sum_j A_j exp(-(t - t_j)^2 / (2 sigma_j^2)).
// sigma_p = FWHM / (2 sqrt(2 ln 2)) is the emitted pulse's; a sub-ray whose footprint cell
// spans a range interval of standard deviation sigma_Rj (a tilted surface, pulse.hpp) is
// stretched to sigma_j^2 = sigma_p^2 + (2 sigma_Rj / c)^2 with its energy kept:
// A_j = P_j sigma_p / sigma_j (EchoContribution::sigma_ns; 0 means sigma_p, A_j = P_j).
// w is sampled at t = k * bin_ns (absolute bins: sample k of the record is bin first_bin + k),
// over [min t_j - 5 sigma_max, max t_j + 5 sigma_max]; each contribution reaches 5 sigma_j.
//
// Echo detection. Candidates are the local maxima of the samples (w[k-1] < w[k] >= w[k+1]),
// in time order. A candidate is a separate echo only if BOTH
//   - it lies at least min_separation (range) from the previous accepted echo's peak, and
//   - the waveform between the two dips below (1 - min_dip) times the smaller of the two peaks;
// otherwise it merges into that echo (whose peak becomes the higher of the two). Defaults:
// min_separation = half the range resolution, c FWHM / 4 (0.3 m for a 4 ns pulse; the peaks of
// two overlapping echoes lie closer than the echoes), and min_dip = 0.1: a smooth tilted plane's
// sampled footprint leaves ripples under 5 % (one echo), while two equal echoes separate from
// about 2.45 sigma_p (0.62 m for 4 ns) on, close to the classic resolution c FWHM / 2.
// Separate echoes split the waveform at the lowest sample between them (shared half and half).
// Each echo is fitted with a Gaussian over its samples of at least kEchoFitFraction (0.2) of its
// peak sample, contiguous around it: the weighted least-squares parabola through ln w with weights
// w^2 (Caruana's algorithm with Guo's weights, a closed-form 3x3 system), exact for a Gaussian.
// Separate echoes overlap, so each is then fitted once more on the samples less the other echoes'
// first fits. The fit gives the echo's time (-> range = c t / 2), amplitude A and width sigma_e.
// Echoes with A below the detection threshold are dropped. Reported per echo: range, amplitude
// (peak power, W), echo width (FWHM of the fitted Gaussian, ns) and the equivalent power: the
// echo's energy (its samples summed over its span, times bin_ns) divided by the energy of a unit-
// peak emitted pulse (sigma_p sqrt(2 pi)). It equals the sum of the P_j that formed the echo even
// when a tilted or rough surface stretches or merges it.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace beamtrace {

inline constexpr double kSpeedOfLight_m_per_s = 299'792'458.0;
/// The echo fit uses the samples of at least this fraction of the echo's peak sample.
inline constexpr double kEchoFitFraction = 0.2;

struct WaveformConfig {
    double pulse_fwhm_ns = 4.0;  ///< emitted pulse width (full width at half maximum)
    double bin_ns = 0.5;         ///< digitiser sample spacing, at most pulse_fwhm_ns / 2
    /// Least range between the peaks of two separate echoes [m]; negative: half the range
    /// resolution, c pulse_fwhm / 4 (0.3 m at 4 ns).
    double min_separation_m = -1.0;
    /// Least relative dip of the waveform between two separate echoes, in [0, 1).
    double min_dip = 0.1;

    /// min_separation_m, or c pulse_fwhm / 4 when it is negative [m].
    [[nodiscard]] double min_separation_or_default_m() const;

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// One sub-ray's contribution: one-way range [m], peak received power of the unstretched pulse
/// [W] and the width of its echo (sigma, ns; 0: the emitted pulse's). The peak of the added
/// Gaussian is power_w sigma_p / sigma_ns, so its energy stays power_w sigma_p sqrt(2 pi).
struct EchoContribution {
    double range_m = 0.0;
    double power_w = 0.0;
    double sigma_ns = 0.0;
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

/// Pulses already summed on the bin grid: samples_w[k] adds to bin first_bin + k. They stand for
/// unstretched pulses (sigma_p) centred from first_range_m to last_range_m, which set the
/// waveform's extent as their contributions would (e.g. a fog's slabs, fog.hpp).
struct BinnedEcho {
    std::int64_t first_bin = 0;
    std::vector<double> samples_w;
    double first_range_m = 0.0;
    double last_range_m = 0.0;
    [[nodiscard]] bool empty() const { return samples_w.empty(); }
    void clear() { samples_w.clear(); }
};

/// The same with `binned` added after the contributions (either may be empty).
void build_waveform(const WaveformConfig& config, std::span<const EchoContribution> contributions,
                    const BinnedEcho& binned, Waveform& out);

/// HELIOS++'s pulse of length L (its scanners' `pulseLength_ns`): p(t) = (t/tau)^2 exp(-t/tau),
/// tau = L / 7, sampled over [0, L). Its FWHM is this factor times L: (x2 - x1) / 7 with
/// x1 = 0.761240, x2 = 4.155921 the roots of x^2 e^-x = 2 e^-2 (half the peak, at x = 2).
inline constexpr double kHeliosPulseFwhmPerLength = 0.48495438154950027;

/// The FWHM [ns] of HELIOS++'s pulse of length `pulse_length_ns` (a 10 ns pulse: 4.85 ns).
[[nodiscard]] inline double helios_pulse_fwhm_ns(double pulse_length_ns) {
    return kHeliosPulseFwhmPerLength * pulse_length_ns;
}

/// The peak power [W] of a Gaussian pulse of energy `energy_j` and FWHM `fwhm_ns`:
/// E / (FWHM sqrt(pi / (4 ln 2))) (its energy is the peak times 1.0645 FWHM).
[[nodiscard]] double gaussian_pulse_peak_power_w(double energy_j, double fwhm_ns);

/// Appends the echoes of `waveform` with amplitude >= threshold_w to `out` in range order.
void detect_echoes(const WaveformConfig& config, const Waveform& waveform, double threshold_w,
                   std::vector<Echo>& out);

/// The same, with the spans whose highest sample is below `unfitted_below_w` (at most
/// threshold_w; the weather's pulses, weather_echoes.hpp) neither fitted nor reported: their
/// first fit, which the refit takes off their neighbours, is the emitted pulse through their
/// highest sample.
void detect_echoes(const WaveformConfig& config, const Waveform& waveform, double threshold_w,
                   double unfitted_below_w, std::vector<Echo>& out);

}  // namespace beamtrace
