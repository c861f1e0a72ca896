#include "beamtrace/physics/fog.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "beamtrace/physics/waveform.hpp"

namespace beamtrace {

namespace {

/// ln(20): the extinction times the MOR (5 % transmission over the MOR).
constexpr double kLn20 = 2.995732273553991;
/// beta * MOR of advection fog [1/sr] (Rasshofer et al. 2011; Hahner et al. 2021).
constexpr double kFogBackscatterTimesMor = 0.046;

bool positive_finite(double x) {
    return x > 0.0 && std::isfinite(x);
}

}  // namespace

std::vector<std::string> OverlapConfig::validate() const {
    std::vector<std::string> p;
    if (!positive_finite(start_m)) {
        // xi(r) / r^2 ~ 1 / r near a start at 0: the fog's echo would be infinite.
        p.emplace_back("overlap_start_m: must be positive");
    }
    if (!std::isfinite(full_m) || !(full_m > start_m)) {
        p.emplace_back("overlap_full_m: must be greater than overlap_start_m");
    }
    return p;
}

double overlap_fraction(const OverlapConfig& overlap, double range_m) {
    if (range_m <= overlap.start_m) {
        return 0.0;
    }
    if (range_m >= overlap.full_m) {
        return 1.0;
    }
    return (range_m - overlap.start_m) / (overlap.full_m - overlap.start_m);
}

std::vector<std::string> FogConfig::validate() const {
    std::vector<std::string> p;
    if (!positive_finite(mor_m)) {
        p.emplace_back("fog.mor_m: must be a positive number of metres");
    } else if (mor_m < 1.0) {
        p.emplace_back("fog.mor_m: below 1 m (the densest fogs measured have a MOR of metres)");
    }
    // Bounds far beyond any fog (MOR 1 m: alpha 3 per m, beta 0.046 per m sr).
    if (extinction_per_m && !(*extinction_per_m >= 0.0 && *extinction_per_m <= 100.0)) {
        p.emplace_back("fog.extinction_per_m: must be in [0, 100] per metre");
    }
    if (backscatter_per_m_sr && !(*backscatter_per_m_sr >= 0.0 && *backscatter_per_m_sr <= 10.0)) {
        p.emplace_back("fog.backscatter_per_m_sr: must be in [0, 10] per metre and steradian");
    }
    return p;
}

double fog_extinction_per_m(const FogConfig& fog) {
    return fog.extinction_per_m.value_or(kLn20 / fog.mor_m);
}

double fog_backscatter_per_m_sr(const FogConfig& fog) {
    return fog.backscatter_per_m_sr.value_or(kFogBackscatterTimesMor / fog.mor_m);
}

void add_soft_target_echo(const SoftTarget& medium, double emitted_power_w, double receiver_gain_m2,
                          double end_m, const SoftTargetSampling& sampling,
                          std::vector<EchoContribution>& out) {
    BeamShare whole{1.0, end_m};
    add_soft_target_echo(medium, emitted_power_w, receiver_gain_m2, std::span(&whole, 1), sampling,
                         out);
}

namespace {

/// Where add_soft_target_echo's walk along the path stands: the next slab's start, the shares
/// ended so far and the weight of those still travelling.
struct SlabWalk {
    double lo = 0.0;
    std::size_t ended = 0;
    double travelling = 0.0;
};

/// Throws unless every share ends at a finite range; sorts them by end; the walk's start.
SlabWalk start_walk(const SoftTarget& medium, std::span<BeamShare> shares) {
    for (const BeamShare& s : shares) {
        if (!std::isfinite(s.end_m)) {
            throw std::invalid_argument("add_soft_target_echo: a share's end must be finite");
        }
    }
    std::sort(shares.begin(), shares.end(),
              [](const BeamShare& a, const BeamShare& b) { return a.end_m < b.end_m; });
    SlabWalk w;
    w.lo = std::max(medium.overlap.start_m, 0.0);
    for (const BeamShare& s : shares) {
        w.travelling += s.weight;  // the weight of the shares not yet ended
    }
    while (w.ended < shares.size() && !(shares[w.ended].end_m > w.lo)) {
        w.travelling -= shares[w.ended++].weight;
    }
    return w;
}

/// The slab's thickness from `lo` on (before any cut).
double slab_step_m(const SoftTarget& medium, const SoftTargetSampling& sampling, double lo) {
    const bool ramp = lo < medium.overlap.full_m && sampling.ramp_slab_m > 0.0;
    return ramp ? std::min(sampling.slab_m, sampling.ramp_slab_m) : sampling.slab_m;
}

/// The slabs from `w` on, as contributions: slabs of width d, cut where a share ends so that
/// each lies within one total weight, until every share has ended or the cut-off.
void walk_slabs(const SoftTarget& medium, double scale, std::span<const BeamShare> shares,
                const SoftTargetSampling& sampling, SlabWalk w,
                std::vector<EchoContribution>& out) {
    const double d = sampling.slab_m;
    for (double lo = w.lo;;) {
        while (w.ended < shares.size() && !(shares[w.ended].end_m > lo)) {
            w.travelling -= shares[w.ended++].weight;
        }
        if (w.ended == shares.size()) {
            break;
        }
        const double hi = std::min(lo + slab_step_m(medium, sampling, lo), shares[w.ended].end_m);
        const double width = hi - lo;
        const double r = lo + width / 2.0;
        const double power = scale * w.travelling * width * overlap_fraction(medium.overlap, r) *
                             std::exp(-2.0 * medium.extinction_per_m * r) / (r * r);
        if (r > medium.overlap.full_m && power < sampling.cutoff_w * (width / d)) {
            break;  // beyond full overlap the integrand only falls
        }
        if (power > 0.0) {
            out.push_back({r, power, 0.0});
        }
        lo = hi;
    }
}

bool usable(const SoftTarget& medium, const SoftTargetSampling& sampling) {
    return medium.backscatter_per_m_sr > 0.0 && sampling.slab_m > 0.0;
}

}  // namespace

void add_soft_target_echo(const SoftTarget& medium, double emitted_power_w, double receiver_gain_m2,
                          std::span<BeamShare> shares, const SoftTargetSampling& sampling,
                          std::vector<EchoContribution>& out) {
    if (!usable(medium, sampling) || shares.empty()) {
        return;
    }
    const SlabWalk w = start_walk(medium, shares);
    const double scale = emitted_power_w * receiver_gain_m2 * medium.backscatter_per_m_sr;
    walk_slabs(medium, scale, shares, sampling, w, out);
}

SoftTargetProfile::SoftTargetProfile(const SoftTarget& medium, double emitted_power_w,
                                     double receiver_gain_m2, const SoftTargetSampling& sampling,
                                     const WaveformConfig& waveform, double max_range_m,
                                     double max_weight)
    : medium_(medium),
      emitted_power_w_(emitted_power_w),
      receiver_gain_m2_(receiver_gain_m2),
      sampling_(sampling),
      bin_ns_(waveform.bin_ns) {
    if (!usable(medium, sampling)) {
        return;
    }
    // The slabs of an uncut walk, up to where the heaviest beam meets the cut-off (included:
    // lighter ones stop there or before).
    constexpr std::size_t kMaxSlabs = std::size_t{1} << 16;
    const double scale_max =
        emitted_power_w * receiver_gain_m2 * medium.backscatter_per_m_sr * max_weight;
    for (double lo = std::max(medium.overlap.start_m, 0.0);
         lo < max_range_m && slabs_.size() < kMaxSlabs;) {
        Slab s;
        s.lo = lo;
        s.hi = lo + slab_step_m(medium, sampling, lo);
        s.width = s.hi - s.lo;
        s.r = lo + s.width / 2.0;
        s.xi = overlap_fraction(medium.overlap, s.r);
        s.transmission = std::exp(-2.0 * medium.extinction_per_m * s.r);
        s.unit_w = s.width * s.xi * s.transmission / (s.r * s.r);
        slabs_.push_back(s);
        first_full_ += s.r > medium.overlap.full_m ? 0 : 1;
        if (below_cutoff(slabs_.size() - 1, scale_max)) {
            break;
        }
        lo = s.hi;
    }
    bin_slabs(waveform);
}

void SoftTargetProfile::bin_slabs(const WaveformConfig& waveform) {
    if (slabs_.empty()) {
        return;
    }
    // Each slab's pulse reaches the bins build_waveform gives it: 5 sigma_p either side.
    const double sigma = waveform.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    const double reach_ns = 5.0 * sigma;
    std::vector<std::int64_t> b0(slabs_.size()), b1(slabs_.size());
    for (std::size_t s = 0; s < slabs_.size(); ++s) {
        const double t = slabs_[s].r * round_trip_ns_per_m();
        b0[s] = static_cast<std::int64_t>(std::floor((t - reach_ns) / bin_ns_));
        b1[s] = static_cast<std::int64_t>(std::ceil((t + reach_ns) / bin_ns_));
    }
    first_bin_ = b0.front();
    const auto bins = static_cast<std::size_t>(b1.back() - first_bin_ + 1);
    slab_last_bin_.resize(slabs_.size());
    slab_first_bin_.resize(slabs_.size());
    for (std::size_t s = 0; s < slabs_.size(); ++s) {
        slab_last_bin_[s] = static_cast<std::uint32_t>(b1[s] - first_bin_);
        slab_first_bin_[s] = static_cast<std::uint32_t>(b0[s] - first_bin_);
    }
    whole_.resize(bins);
    bin_first_slab_.resize(bins);
    bin_offset_.resize(bins + 1);
    prefix_.clear();
    const double inv_two_var = 1.0 / (2.0 * sigma * sigma);
    std::size_t lo = 0, hi = 0;  // the slabs reaching bin b: [lo, hi)
    for (std::size_t k = 0; k < bins; ++k) {
        const std::int64_t b = first_bin_ + static_cast<std::int64_t>(k);
        while (lo < slabs_.size() && b1[lo] < b) {
            ++lo;
        }
        while (hi < slabs_.size() && b0[hi] <= b) {
            ++hi;
        }
        bin_first_slab_[k] = static_cast<std::uint32_t>(lo);
        bin_offset_[k] = static_cast<std::uint32_t>(prefix_.size());
        double sum = 0.0;
        prefix_.push_back(sum);
        for (std::size_t s = lo; s < hi; ++s) {
            const double dt =
                static_cast<double>(b) * bin_ns_ - slabs_[s].r * round_trip_ns_per_m();
            sum += slabs_[s].unit_w * std::exp(-dt * dt * inv_two_var);
            prefix_.push_back(sum);
        }
        whole_[k] = sum;
    }
    bin_offset_[bins] = static_cast<std::uint32_t>(prefix_.size());
}

bool SoftTargetProfile::below_cutoff(std::size_t s, double scale_w) const {
    const Slab& x = slabs_[s];
    // add_soft_target_echo's power and test, with the same operations in the same order.
    const double power = scale_w * x.width * x.xi * x.transmission / (x.r * x.r);
    return x.r > medium_.overlap.full_m &&
           power < sampling_.cutoff_w * (x.width / sampling_.slab_m);
}

void SoftTargetProfile::echo(std::span<BeamShare> shares, SoftTargetEcho& binned,
                             std::vector<EchoContribution>& out) const {
    binned.clear();
    if (!usable(medium_, sampling_) || shares.empty()) {
        return;
    }
    SlabWalk w = start_walk(medium_, shares);
    if (w.ended == shares.size()) {
        return;
    }
    const double scale = emitted_power_w_ * receiver_gain_m2_ * medium_.backscatter_per_m_sr;
    const double scale_w = scale * w.travelling;
    // The table's slabs that no share cuts, then the first of them at the cut-off (the test is
    // monotonic beyond full overlap: the integrand only falls).
    const double end_m = shares[w.ended].end_m;
    const auto uncut = static_cast<std::size_t>(
        std::upper_bound(slabs_.begin(), slabs_.end(), end_m,
                         [](double e, const Slab& s) { return e < s.hi; }) -
        slabs_.begin());
    std::size_t lo = std::min(first_full_, uncut), hi = uncut;
    while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (below_cutoff(mid, scale_w)) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    const std::size_t n = lo;
    fill_bins(n, scale_w, binned);
    if (n == uncut && uncut > 0) {
        w.lo = slabs_[uncut - 1].hi;
    }
    if (n == uncut) {
        walk_slabs(medium_, scale, shares, sampling_, w, out);
    }
}

void SoftTargetProfile::fill_bins(std::size_t n, double scale_w, SoftTargetEcho& binned) const {
    binned.slabs = n;
    binned.scale_w = scale_w;
    if (n == 0) {
        return;
    }
    BinnedEcho& e = binned.binned;
    e.first_bin = first_bin_;
    e.first_range_m = slabs_.front().r;
    e.last_range_m = slabs_[n - 1].r;
    const std::size_t bins = slab_last_bin_[n - 1] + 1;
    e.samples_w.resize(bins);
    // Bins before the first one slab n reaches hold all their slabs.
    const std::size_t whole =
        n < slabs_.size() ? std::min<std::size_t>(slab_first_bin_[n], bins) : bins;
    for (std::size_t k = 0; k < whole; ++k) {
        e.samples_w[k] = scale_w * whole_[k];
    }
    for (std::size_t k = whole; k < bins; ++k) {
        const std::size_t first = bin_first_slab_[k];
        const std::size_t len = bin_offset_[k + 1] - bin_offset_[k] - 1;
        const std::size_t count = n > first ? std::min(n - first, len) : 0;
        e.samples_w[k] = scale_w * prefix_[bin_offset_[k] + count];
    }
}

double SoftTargetProfile::share_at(const SoftTargetEcho& binned, double range_m,
                                   double sigma_m) const {
    constexpr double kReach = 12.0;  // exp(-72): far below a double's precision
    const std::size_t n = binned.slabs;
    auto s = static_cast<std::size_t>(
        std::lower_bound(slabs_.begin(), slabs_.begin() + static_cast<std::ptrdiff_t>(n),
                         range_m - kReach * sigma_m,
                         [](const Slab& x, double r) { return x.r < r; }) -
        slabs_.begin());
    // exp(-x^2 / 2) along slabs of equal width by recurrence: x steps by delta = width / sigma,
    // the term by exp(-x delta - delta^2 / 2), that factor by exp(-delta^2) per step.
    double sum = 0.0, term = 0.0, factor = 0.0, step = 0.0, width = -1.0;
    for (; s < n && slabs_[s].r <= range_m + kReach * sigma_m; ++s) {
        const Slab& x = slabs_[s];
        if (std::abs(x.width - width) > 1e-9 * x.width) {
            const double u = (x.r - range_m) / sigma_m;
            const double delta = x.width / sigma_m;
            term = std::exp(-0.5 * u * u);
            factor = std::exp(-u * delta - 0.5 * delta * delta);
            step = std::exp(-delta * delta);
            width = x.width;
        }
        sum += x.unit_w * term;
        term *= factor;
        factor *= step;
    }
    return binned.scale_w * sum / sigma_m;
}

}  // namespace beamtrace
