#include "beamtrace/physics/fog.hpp"

#include <algorithm>
#include <cmath>

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
    }
    if (extinction_per_m && !(*extinction_per_m >= 0.0 && std::isfinite(*extinction_per_m))) {
        p.emplace_back("fog.extinction_per_m: must be zero or positive");
    }
    if (backscatter_per_m_sr &&
        !(*backscatter_per_m_sr >= 0.0 && std::isfinite(*backscatter_per_m_sr))) {
        p.emplace_back("fog.backscatter_per_m_sr: must be zero or positive");
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
    if (!(medium.backscatter_per_m_sr > 0.0) || !(sampling.slab_m > 0.0)) {
        return;
    }
    const double d = sampling.slab_m;
    const double scale = emitted_power_w * receiver_gain_m2 * medium.backscatter_per_m_sr;
    const double begin_m = std::max(medium.overlap.start_m, 0.0);
    for (std::size_t k = 0;; ++k) {
        const double lo = begin_m + static_cast<double>(k) * d;
        if (!(lo < end_m)) {
            break;
        }
        const double width = std::min(d, end_m - lo);
        const double r = lo + width / 2.0;
        const double power = scale * width * overlap_fraction(medium.overlap, r) *
                             std::exp(-2.0 * medium.extinction_per_m * r) / (r * r);
        if (r > medium.overlap.full_m && power < sampling.cutoff_w * (width / d)) {
            break;  // beyond full overlap the integrand only falls
        }
        if (power > 0.0) {
            out.push_back({r, power, 0.0});
        }
    }
}

}  // namespace beamtrace
