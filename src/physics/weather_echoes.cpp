#include "beamtrace/physics/weather_echoes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

namespace beamtrace {

namespace {

/// The bins [b0, b1] that build_waveform samples for a contribution (its index) or for the
/// binned echo (index kBinned).
struct Reach {
    std::int64_t b0 = 0, b1 = 0;
    std::size_t index = 0;
};
constexpr std::size_t kBinned = std::numeric_limits<std::size_t>::max();

/// A pulse alone is answered in closed form when its sigma spans at least this many bins: its
/// fit (samples of at least 0.2 of the peak, within 1.79 sigma) then keeps 5 samples or more, and
/// the sampled sum is the Gaussian's integral (the aliasing term exp(-2 pi^2 sigma^2 / h^2) is
/// below 1e-19).
constexpr double kClosedFormSigmaBins = 1.5;

/// A span whose highest sample is below this fraction of the threshold is not fitted
/// (detect_echoes) and not reported: a lone pulse's fit peaks at most exp(h^2 / (8 sigma^2))
/// above its highest sample (1.1 % with 0.5 ns bins and a 4 ns pulse), so only echoes that
/// close to the threshold are lost.
constexpr double kUnfittedFraction = 1.0;

/// What detect_echoes_in_groups works in, kept per thread (no allocation per pulse).
struct GroupScratch {
    std::vector<Reach> reaches;
    std::vector<std::size_t> members;
    std::vector<EchoContribution> group;
    std::vector<double> peaks_w;  ///< each group member's peak (a stretched echo's is lower)
    Waveform waveform;
};

double pulse_sigma_ns(const WaveformConfig& config) {
    return config.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
}

/// Every contribution's reach and the binned echo's, sorted by first bin.
void find_reaches(const WaveformConfig& config, std::span<const EchoContribution> contributions,
                  const BinnedEcho& binned, double reach_sigmas, std::vector<Reach>& out) {
    out.clear();
    const double sigma_p = pulse_sigma_ns(config), h = config.bin_ns;
    const auto reach = [&](double t0_ns, double t1_ns, double reach_ns, std::size_t index) {
        out.push_back({static_cast<std::int64_t>(std::floor((t0_ns - reach_ns) / h)),
                       static_cast<std::int64_t>(std::ceil((t1_ns + reach_ns) / h)), index});
    };
    for (std::size_t i = 0; i < contributions.size(); ++i) {
        const EchoContribution& c = contributions[i];
        const double t = c.range_m * round_trip_ns_per_m();
        reach(t, t, reach_sigmas * (c.sigma_ns > 0 ? c.sigma_ns : sigma_p), i);
    }
    if (!binned.empty()) {
        reach(binned.first_range_m * round_trip_ns_per_m(),
              binned.last_range_m * round_trip_ns_per_m(), kExactReachSigmas * sigma_p, kBinned);
    }
    std::sort(out.begin(), out.end(), [](const Reach& a, const Reach& b) {
        return a.b0 != b.b0 ? a.b0 < b.b0 : a.index < b.index;
    });
}

/// The equivalent power of a lone pulse as detect_echoes sums it (its span the whole record
/// [b0 h, b1 h] that build_waveform samples, the end samples counted half), in closed form: the
/// pulse's energy times the share of the Gaussian inside the record. With sigma of at least
/// kClosedFormSigmaBins bins the trapezoid sum is that integral within 6e-7 (Euler-Maclaurin:
/// h^2 / 12 of the slopes at the ends, beyond 5 sigma; the aliasing term is below 1e-19).
double lone_energy(const WaveformConfig& config, const EchoContribution& c) {
    const double sigma = c.sigma_ns > 0 ? c.sigma_ns : pulse_sigma_ns(config), h = config.bin_ns;
    const double t = c.range_m * round_trip_ns_per_m();
    const double lo_ns = std::floor((t - 5.0 * sigma) / h) * h;
    const double hi_ns = std::ceil((t + 5.0 * sigma) / h) * h;
    const double per_ns = 1.0 / (sigma * std::numbers::sqrt2);
    return c.power_w *
           (1.0 - 0.5 * std::erfc((hi_ns - t) * per_ns) - 0.5 * std::erfc((t - lo_ns) * per_ns));
}

/// Relative room left for the rounding of the sampled waveform (its recurrences and sums) and of
/// the bound's own exps, far above either.
constexpr double kBoundRoom = 1e-9;

/// True when no sample of the group's waveform (its pulses `peaks_w`, all below the threshold, at
/// `group`'s ranges; no binned echo) reaches `threshold_w`. A time t lies nearest to some pulse
/// i's centre, so every other pulse j is at least half their distance d_ij from t: the waveform
/// is at most max_i (P_i + sum_j P_j exp(-(d_ij / 2)^2 / (2 sigma_j^2))) there.
bool group_below(const WaveformConfig& config, std::span<const EchoContribution> group,
                 std::span<const double> peaks_w, double threshold_w) {
    const double sigma_p = pulse_sigma_ns(config);
    for (std::size_t i = 0; i < group.size(); ++i) {
        double w = peaks_w[i];
        for (std::size_t j = 0; j < group.size() && w * (1.0 + kBoundRoom) < threshold_w; ++j) {
            if (j != i) {
                const double half_ns =
                    0.5 * std::abs(group[i].range_m - group[j].range_m) * round_trip_ns_per_m();
                const double x = half_ns / (group[j].sigma_ns > 0 ? group[j].sigma_ns : sigma_p);
                w += peaks_w[j] * std::exp(-0.5 * x * x);
            }
        }
        if (!(w * (1.0 + kBoundRoom) < threshold_w)) {
            return false;
        }
    }
    return true;
}

/// The echoes of one group (`members`, ascending: the contributions' order, the binned echo
/// last).
void detect_group(const WaveformConfig& config, std::span<const EchoContribution> contributions,
                  const BinnedEcho& binned, double threshold_w, GroupScratch& s,
                  std::vector<Echo>& out) {
    const double sigma_p = pulse_sigma_ns(config);
    if (s.members.size() == 1 && s.members[0] != kBinned) {
        const EchoContribution& c = contributions[s.members[0]];
        const double sigma = c.sigma_ns > 0 ? c.sigma_ns : sigma_p;
        if (sigma >= kClosedFormSigmaBins * config.bin_ns) {
            // What the fit of the sampled Gaussian gives (waveform.hpp): the stretched echo
            // keeps its energy, its peak drops as sigma_p / sigma; the energy in closed form.
            Echo e;
            e.range_m = c.range_m;
            e.amplitude_w = c.sigma_ns > 0 ? c.power_w * (sigma_p / sigma) : c.power_w;
            e.width_ns = sigma * (2.0 * std::sqrt(2.0 * std::log(2.0)));  // FWHM
            if (e.amplitude_w >= threshold_w) {
                e.power_w = lone_energy(config, c);
                out.push_back(e);
            }
            return;
        }
    }
    s.group.clear();
    s.peaks_w.clear();
    bool with_binned = false;
    double peaks_w = 0.0, highest_w = 0.0;  // the waveform is nowhere higher than their sum
    for (const std::size_t m : s.members) {
        if (m == kBinned) {
            with_binned = true;
        } else {
            const EchoContribution& c = contributions[m];
            s.group.push_back(c);
            s.peaks_w.push_back(c.sigma_ns > 0 ? c.power_w * (sigma_p / c.sigma_ns) : c.power_w);
            peaks_w += s.peaks_w.back();
            highest_w = std::max(highest_w, s.peaks_w.back());
        }
    }
    // Every span's top is below it (kUnfittedFraction 1): none is reported. The closer bound
    // when no pulse alone reaches it (faint drops apart from each other).
    if (!with_binned &&
        (peaks_w < kUnfittedFraction * threshold_w ||
         (highest_w < kUnfittedFraction * threshold_w &&
          group_below(config, s.group, s.peaks_w, kUnfittedFraction * threshold_w)))) {
        return;
    }
    static const BinnedEcho kNone;
    build_waveform(config, s.group, with_binned ? binned : kNone, s.waveform);
    // With the fog's echo (its slabs' ripples are spans too) every span is fitted, as before.
    detect_echoes(config, s.waveform, threshold_w,
                  with_binned ? 0.0 : kUnfittedFraction * threshold_w, out);
}

}  // namespace

void detect_echoes_in_groups(const WaveformConfig& config,
                             std::span<const EchoContribution> contributions,
                             const BinnedEcho& binned, double threshold_w, std::vector<Echo>& out,
                             double reach_sigmas) {
    thread_local GroupScratch s;
    find_reaches(config, contributions, binned, reach_sigmas, s.reaches);
    // Groups apart by the least separation at least, so that their tops are separate echoes in
    // the whole waveform too (and by one bin: a 0 sample between them).
    const double min_separation_ns = config.min_separation_or_default_m() * round_trip_ns_per_m();
    const auto gap = std::max<std::int64_t>(
        1, static_cast<std::int64_t>(std::ceil(min_separation_ns / config.bin_ns)));
    for (std::size_t i = 0; i < s.reaches.size();) {
        s.members.assign(1, s.reaches[i].index);
        std::int64_t end = s.reaches[i].b1;
        for (++i; i < s.reaches.size() && s.reaches[i].b0 <= end + gap; ++i) {
            s.members.push_back(s.reaches[i].index);
            end = std::max(end, s.reaches[i].b1);
        }
        std::sort(s.members.begin(), s.members.end());
        detect_group(config, contributions, binned, threshold_w, s, out);
    }
}

}  // namespace beamtrace
