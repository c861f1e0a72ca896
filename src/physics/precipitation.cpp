#include "beamtrace/physics/precipitation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "beamtrace/core/name_table.hpp"

namespace beamtrace {

namespace {

constexpr NameTable<PrecipitationKind, 2> kKinds{
    "precipitation", {{{PrecipitationKind::rain, "rain"}, {PrecipitationKind::snow, "snow"}}}};

constexpr double kMmPerM = 1000.0;

}  // namespace

std::string_view to_string(PrecipitationKind kind) {
    return kKinds.to_string(kind);
}

PrecipitationKind parse_precipitation_kind(std::string_view name) {
    return kKinds.parse(name);
}

DropSizeDistribution drop_size_distribution(PrecipitationKind kind, double rate_mm_h) {
    if (kind == PrecipitationKind::rain) {
        return {8000.0, 4.1 * std::pow(rate_mm_h, -0.21)};
    }
    return {3800.0 * std::pow(rate_mm_h, -0.87), 2.55 * std::pow(rate_mm_h, -0.48)};
}

double number_density_per_m3(const DropSizeDistribution& dsd) {
    return dsd.n0_per_m3_mm / dsd.slope_per_mm;
}

double extinction_per_m(const DropSizeDistribution& dsd) {
    // 2 * (pi / 4) * integral D^2 N(D) dD = pi n0 / slope^3 [mm^2 / m^3]
    const double mm2_per_m3 = std::numbers::pi * dsd.n0_per_m3_mm / std::pow(dsd.slope_per_mm, 3);
    return mm2_per_m3 / (kMmPerM * kMmPerM);
}

double default_particle_albedo(PrecipitationKind kind) {
    return kind == PrecipitationKind::rain ? 0.02 : 0.8;
}

ParticleSampler::ParticleSampler(const DropSizeDistribution& dsd, double albedo,
                                 const ParticleBeam& beam, const ParticleCell& cell,
                                 std::size_t table_size)
    : dsd_(dsd),
      albedo_(albedo),
      beam_(beam),
      cell_(cell),
      tan_half_angle_(std::tan(beam.half_angle_rad)) {
    if (table_size < 2 || !(beam.max_range_m > beam.start_m) || !(beam.start_m > 0.0) ||
        !(beam.floor_w > 0.0)) {
        throw std::invalid_argument(
            "ParticleSampler: needs 0 < start_m < max_range_m, floor_w > 0, 2+ table entries");
    }
    step_m_ = (beam.max_range_m - beam.start_m) / static_cast<double>(table_size - 1);
    cumulative_.resize(table_size);
    cumulative_[0] = 0.0;
    for (std::size_t k = 1; k < table_size; ++k) {
        const double a = beam.start_m + static_cast<double>(k - 1) * step_m_;
        const double b = a + step_m_;
        // Simpson's rule on each step.
        const double piece =
            (density_per_m(a) + 4.0 * density_per_m((a + b) / 2.0) + density_per_m(b)) / 6.0;
        cumulative_[k] = cumulative_[k - 1] + piece * step_m_;
    }
    // range_at's starting points: the upper bound of each of table_size equal steps of mu.
    guide_.resize(table_size);
    guide_per_count_ =
        cumulative_.back() > 0.0 ? static_cast<double>(table_size) / cumulative_.back() : 0.0;
    for (std::size_t j = 0; j < table_size; ++j) {
        const double count = static_cast<double>(j) / guide_per_count_;
        guide_[j] = static_cast<std::size_t>(
            std::upper_bound(cumulative_.begin(), cumulative_.end(), count) - cumulative_.begin());
    }
}

double ParticleSampler::cell_area_m2(double range_m) const {
    const double radius = beam_.exit_radius_m + range_m * tan_half_angle_;
    return cell_.area_fraction * std::numbers::pi * radius * radius;
}

ParticleSampler::AtRange ParticleSampler::at_range(double range_m) const {
    return {range_m, cell_area_m2(range_m), overlap_fraction(beam_.overlap, range_m),
            std::exp(-2.0 * beam_.extinction_per_m * range_m)};
}

double ParticleSampler::echo_power_w(double diameter_m, const AtRange& at) const {
    const double cross_section = std::numbers::pi * diameter_m * diameter_m / 4.0;
    const double blocked = std::min(1.0, cross_section / at.area_m2);
    return 2.0 / 3.0 * albedo_ / std::numbers::pi * blocked * cell_.energy_fraction *
           beam_.emitted_power_w * beam_.receiver_gain_m2 * at.overlap * at.transmission /
           (at.range_m * at.range_m);
}

double ParticleSampler::echo_power_w(double diameter_m, double range_m) const {
    return echo_power_w(diameter_m, at_range(range_m));
}

double ParticleSampler::least_diameter_m(const AtRange& at) const {
    // The strongest echo at this range: a particle filling the cell (blocked fraction 1).
    const double area = at.area_m2;
    const double full_cell = echo_power_w(std::sqrt(4.0 * area / std::numbers::pi), at);
    if (!(full_cell >= beam_.floor_w)) {
        return std::numeric_limits<double>::infinity();
    }
    // echo_power_w grows as D^2 below a full cell: solve it for the floor.
    const double d2 = beam_.floor_w / full_cell * (4.0 * area / std::numbers::pi);
    return std::sqrt(d2);
}

double ParticleSampler::least_diameter_m(double range_m) const {
    return least_diameter_m(at_range(range_m));
}

double ParticleSampler::density_per_m(double range_m) const {
    const double d_mm = least_diameter_m(range_m) * kMmPerM;
    if (!std::isfinite(d_mm)) {
        return 0.0;
    }
    return cell_area_m2(range_m) * number_density_per_m3(dsd_) *
           std::exp(-dsd_.slope_per_mm * d_mm);
}

double ParticleSampler::expected_count(double end_m) const {
    const double x =
        (std::clamp(end_m, beam_.start_m, beam_.max_range_m) - beam_.start_m) / step_m_;
    const auto k = std::min(static_cast<std::size_t>(x), cumulative_.size() - 2);
    const double t = x - static_cast<double>(k);
    return cumulative_[k] + t * (cumulative_[k + 1] - cumulative_[k]);
}

std::size_t ParticleSampler::upper_bound_of(double count) const {
    // From the guide's entry for count's step of mu, walked to the first entry above count:
    // std::upper_bound's index for any start, as the table does not decrease (a step or two on
    // average instead of a binary search over the table).
    const double at = count * guide_per_count_;
    std::size_t i =
        at >= 0.0
            ? guide_[std::min(static_cast<std::size_t>(std::min(at, 0x1p62)), guide_.size() - 1)]
            : 0;
    const std::size_t n = cumulative_.size();
    while (i < n && !(count < cumulative_[i])) {
        ++i;
    }
    while (i > 0 && count < cumulative_[i - 1]) {
        --i;
    }
    return i;
}

double ParticleSampler::range_at(double count) const {
    const auto k = static_cast<std::size_t>(
        std::clamp<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(upper_bound_of(count)) - 1, 0,
                                   static_cast<std::ptrdiff_t>(cumulative_.size()) - 2));
    const double width = cumulative_[k + 1] - cumulative_[k];
    const double t = width > 0.0 ? std::clamp((count - cumulative_[k]) / width, 0.0, 1.0) : 0.0;
    return beam_.start_m + (static_cast<double>(k) + t) * step_m_;
}

void ParticleSampler::sample(CounterRng& rng, double end_m, std::vector<Particle>& out) const {
    const double mean = expected_count(end_m);
    const std::uint64_t n = poisson_count(rng, mean);
    for (std::uint64_t i = 0; i < n; ++i) {
        // The range's terms once for the particle's least diameter, echo and blocked fraction.
        const AtRange at = at_range(range_at(rng.uniform() * mean));
        const double d_m =
            least_diameter_m(at) - std::log(rng.uniform_open()) / dsd_.slope_per_mm / kMmPerM;
        const double cross_section = std::numbers::pi * d_m * d_m / 4.0;
        out.push_back(
            {at.range_m, d_m, echo_power_w(d_m, at), std::min(1.0, cross_section / at.area_m2)});
    }
}

std::uint64_t poisson_count(CounterRng& rng, double mean) {
    if (!(mean > 0.0)) {
        return 0;
    }
    constexpr double kLargest = 200.0;  // exp(-200) is still a normal double
    std::uint64_t total = 0;
    for (double left = mean; left > 0.0; left -= kLargest) {
        const double mu = std::min(left, kLargest);
        double p = std::exp(-mu);
        double cumulative = p;
        const double u = rng.uniform();
        std::uint64_t k = 0;
        while (u >= cumulative && p > 0.0) {
            ++k;
            p *= mu / static_cast<double>(k);
            cumulative += p;
        }
        total += k;
    }
    return total;
}

}  // namespace beamtrace
