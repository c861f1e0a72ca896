#include "beamtrace/physics/fog.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

void add_soft_target_echo(const SoftTarget& medium, double emitted_power_w, double receiver_gain_m2,
                          std::span<BeamShare> shares, const SoftTargetSampling& sampling,
                          std::vector<EchoContribution>& out) {
    if (!(medium.backscatter_per_m_sr > 0.0) || !(sampling.slab_m > 0.0) || shares.empty()) {
        return;
    }
    for (const BeamShare& s : shares) {
        if (!std::isfinite(s.end_m)) {
            throw std::invalid_argument("add_soft_target_echo: a share's end must be finite");
        }
    }
    std::sort(shares.begin(), shares.end(),
              [](const BeamShare& a, const BeamShare& b) { return a.end_m < b.end_m; });
    double travelling = 0.0;  // the weight of the shares not yet ended
    for (const BeamShare& s : shares) {
        travelling += s.weight;
    }
    const double d = sampling.slab_m;
    const double scale = emitted_power_w * receiver_gain_m2 * medium.backscatter_per_m_sr;
    std::size_t ended = 0;
    // Slabs of width d, cut where a share ends so that each lies within one total weight.
    for (double lo = std::max(medium.overlap.start_m, 0.0);;) {
        while (ended < shares.size() && !(shares[ended].end_m > lo)) {
            travelling -= shares[ended++].weight;
        }
        if (ended == shares.size()) {
            break;
        }
        const bool ramp = lo < medium.overlap.full_m && sampling.ramp_slab_m > 0.0;
        const double hi =
            std::min(lo + (ramp ? std::min(d, sampling.ramp_slab_m) : d), shares[ended].end_m);
        const double width = hi - lo;
        const double r = lo + width / 2.0;
        const double power = scale * travelling * width * overlap_fraction(medium.overlap, r) *
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

}  // namespace beamtrace
