#include "beamtrace/physics/waveform.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace beamtrace {
namespace {

/// FWHM / sigma of a Gaussian.
const double kFwhmPerSigma = 2.0 * std::sqrt(2.0 * std::log(2.0));
const double kSqrtTwoPi = std::sqrt(2.0 * std::numbers::pi);

}  // namespace

std::vector<std::string> WaveformConfig::validate() const {
    std::vector<std::string> p;
    if (!(pulse_fwhm_ns > 0) || !std::isfinite(pulse_fwhm_ns)) {
        p.emplace_back("waveform: pulse_fwhm_ns must be positive");
    }
    if (!(bin_ns > 0) || !std::isfinite(bin_ns)) {
        p.emplace_back("waveform: bin_ns must be positive");
    } else if (bin_ns > pulse_fwhm_ns / 2.0) {
        p.emplace_back("waveform: bin_ns must be at most pulse_fwhm_ns / 2");
    }
    return p;
}

void build_waveform(const WaveformConfig& config, std::span<const EchoContribution> contributions,
                    Waveform& out) {
    out.bin_ns = config.bin_ns;
    out.first_bin = 0;
    out.samples_w.clear();
    if (contributions.empty()) {
        return;
    }
    const double sigma_ns = config.pulse_fwhm_ns / kFwhmPerSigma;
    const double reach_ns = 5.0 * sigma_ns;
    double t_lo = contributions[0].range_m, t_hi = t_lo;
    for (const auto& c : contributions) {
        t_lo = std::min(t_lo, c.range_m);
        t_hi = std::max(t_hi, c.range_m);
    }
    t_lo = t_lo * round_trip_ns_per_m() - reach_ns;
    t_hi = t_hi * round_trip_ns_per_m() + reach_ns;
    const auto first = static_cast<std::int64_t>(std::floor(t_lo / config.bin_ns));
    const auto last = static_cast<std::int64_t>(std::ceil(t_hi / config.bin_ns));
    out.first_bin = first;
    out.samples_w.assign(static_cast<std::size_t>(last - first + 1), 0.0);
    const double inv_two_var = 1.0 / (2.0 * sigma_ns * sigma_ns);
    for (const auto& c : contributions) {
        const double t = c.range_m * round_trip_ns_per_m();
        const auto b0 =
            std::max(first, static_cast<std::int64_t>(std::floor((t - reach_ns) / config.bin_ns)));
        const auto b1 =
            std::min(last, static_cast<std::int64_t>(std::ceil((t + reach_ns) / config.bin_ns)));
        // exp(-k dt^2) along the bins by recurrence (three exp calls per contribution): the
        // ratio of consecutive samples is exp(-k (2 dt h + h^2)), itself scaled by exp(-2 k h^2)
        // per step.
        const double h = config.bin_ns;
        const double dt0 = static_cast<double>(b0) * h - t;
        double g = c.power_w * std::exp(-dt0 * dt0 * inv_two_var);
        double ratio = std::exp(-(2.0 * dt0 * h + h * h) * inv_two_var);
        const double ratio_step = std::exp(-2.0 * h * h * inv_two_var);
        double* y = out.samples_w.data() + (b0 - first);
        for (std::int64_t b = b0; b <= b1; ++b) {
            *y++ += g;
            g *= ratio;
            ratio *= ratio_step;
        }
    }
}

void detect_echoes(const WaveformConfig& config, const Waveform& waveform, double threshold_w,
                   std::vector<Echo>& out) {
    const auto& y = waveform.samples_w;
    const double sigma_ns = config.pulse_fwhm_ns / kFwhmPerSigma;
    const double h = waveform.bin_ns;
    for (std::size_t k = 1; k + 1 < y.size(); ++k) {
        if (!(y[k] > y[k - 1] && y[k] >= y[k + 1])) {
            continue;
        }
        // Gaussian through the three samples: ln y is a parabola A' - (t - m)^2 / (2 s^2).
        double offset_ns = 0.0, sigma_e = sigma_ns, amplitude = y[k];
        if (y[k - 1] > 0 && y[k + 1] > 0) {
            const double lm = std::log(y[k - 1]), l0 = std::log(y[k]), lp = std::log(y[k + 1]);
            const double d2 = lm - 2.0 * l0 + lp;
            if (d2 < 0) {
                sigma_e = h / std::sqrt(-d2);
                offset_ns = h * (lm - lp) / (2.0 * d2);
                amplitude = std::exp(l0 + offset_ns * offset_ns / (2.0 * sigma_e * sigma_e));
            }
        }
        if (!(amplitude >= threshold_w)) {
            continue;
        }
        Echo e;
        e.range_m = (waveform.time_ns(k) + offset_ns) / round_trip_ns_per_m();
        e.amplitude_w = amplitude;
        e.width_ns = sigma_e * kFwhmPerSigma;
        // Energy between the valleys either side (the valley samples shared half and half).
        std::size_t lo = k, hi = k;
        while (lo > 0 && y[lo - 1] <= y[lo]) {
            --lo;
        }
        while (hi + 1 < y.size() && y[hi + 1] <= y[hi]) {
            ++hi;
        }
        double sum = 0.5 * (y[lo] + y[hi]);
        for (std::size_t j = lo + 1; j < hi; ++j) {
            sum += y[j];
        }
        e.power_w = sum * h / (sigma_ns * kSqrtTwoPi);
        out.push_back(e);
    }
}

}  // namespace beamtrace
