#include "beamtrace/physics/weather_medium.hpp"

#include <algorithm>
#include <cmath>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

namespace {

/// Slabs of the fog's integral: half the pulse's c sigma_p / 2. Gaussians spaced half a sigma
/// apart sum to their integral within 1e-30 (Poisson summation: 2 exp(-2 pi^2 4)); what is
/// left is the midpoint rule's error on the slowly varying xi exp(-2 alpha r) / r^2, below
/// 0.5 % beyond the overlap ramp.
double fog_slab_m(const WaveformConfig& waveform) {
    const double sigma_ns = waveform.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    return sigma_ns / round_trip_ns_per_m() / 2.0;
}

/// The medium's slabs and particles weaker than this fraction of the threshold are left out.
constexpr double kFogCutoffFraction = 1e-3;
/// The largest particle considered when bounding the particles' reach [m].
constexpr double kLargestParticle_m = 0.01;
/// Ranges where the two-way transmission exp(-2 alpha r) falls below e^-28 (1e-12) are not
/// considered.
constexpr double kOpticalDepthLimit = 28.0;

/// The farthest range in [lo, hi] at which a particle of kLargestParticle_m still reaches the
/// floor (bisection; beyond full overlap, lo, its echo only falls with range).
double particle_reach_m(const ParticleSampler& s, double lo, double hi) {
    if (s.least_diameter_m(hi) <= kLargestParticle_m) {
        return hi;
    }
    for (int i = 0; i < 60; ++i) {
        const double mid = (lo + hi) / 2.0;
        (s.least_diameter_m(mid) <= kLargestParticle_m ? lo : hi) = mid;
    }
    return hi;
}

}  // namespace

WeatherMedium::WeatherMedium(const WeatherConfig& weather, const RadiometryConfig& radiometry,
                             const BeamConfig& beam, const WaveformConfig& waveform,
                             double extinction_per_m)
    : weather_(weather),
      emitted_power_w_(radiometry.peak_power_w),
      receiver_gain_m2_(radiometry.system_efficiency * aperture_area_m2(radiometry)) {
    if (weather.clear_air()) {
        return;
    }
    max_range_m_ = kOpticalDepthLimit / (2.0 * std::max(extinction_per_m, 1e-12));
    if (weather.fog) {
        fog_ = {fog_backscatter_per_m_sr(*weather.fog), extinction_per_m, weather.overlap};
        fog_sampling_ = {fog_slab_m(waveform), fog_slab_m(waveform) / 5.0,
                         kFogCutoffFraction * radiometry.detection_threshold_w};
        fog_profile_ = SoftTargetProfile(fog_, emitted_power_w_, receiver_gain_m2_, fog_sampling_,
                                         waveform, max_range_m_);
    }
    if (const auto& p = weather.precipitation) {
        if (!(beam.divergence_rad > 0.0) && !(beam.exit_diameter_m > 0.0)) {
            throw ConfigError(std::string("weather.") + std::string(to_string(p->kind)) +
                              ": the beam needs a volume to hold particles: set "
                              "physics.beam.divergence_mrad (and exit_diameter_m)");
        }
        // A medium so dense that nothing comes back from beyond the overlap ramp: no particle
        // is drawn (they still extinguish the beam).
        if (max_range_m_ > weather.overlap.full_m + 1.0) {
            particles_.emplace(particle_sampler(weather, *p, radiometry, beam, extinction_per_m));
            particle_effect_ = particle_effect(p->kind);
            // Resolved particles (docs/weather.md): each drop apart from its neighbours is its
            // own pulse; the fog's slabs keep the exact split.
            if (!weather.fog) {
                group_reach_sigmas_ = kResolvedReachSigmas;
            }
        }
    }
}

ParticleSampler WeatherMedium::particle_sampler(const WeatherConfig& weather,
                                                const PrecipitationConfig& p,
                                                const RadiometryConfig& radiometry,
                                                const BeamConfig& beam,
                                                double extinction_per_m) const {
    ParticleBeam b;
    b.exit_radius_m = beam.exit_diameter_m / 2.0;
    b.half_angle_rad = beam.divergence_rad / 2.0;
    b.emitted_power_w = emitted_power_w_;
    b.receiver_gain_m2 = receiver_gain_m2_;
    b.extinction_per_m = extinction_per_m;
    b.floor_w = p.floor_fraction * radiometry.detection_threshold_w;
    b.start_m = weather.overlap.start_m;
    b.overlap = weather.overlap;
    b.max_range_m = max_range_m_;
    const auto dsd = drop_size_distribution(p.kind, p.rate_mm_h);
    const double albedo = p.particle_albedo.value_or(default_particle_albedo(p.kind));
    // The table spans the particles' reach only, in steps of at most 2 cm.
    const ParticleSampler probe(dsd, albedo, b, {}, 2);
    b.max_range_m = std::max(particle_reach_m(probe, weather.overlap.full_m, max_range_m_),
                             weather.overlap.full_m + 1.0);
    const auto steps = static_cast<std::size_t>((b.max_range_m - b.start_m) / 0.02);
    return {dsd, albedo, b, ParticleCell{},
            std::clamp<std::size_t>(steps, 1024, std::size_t{1} << 18)};
}

void WeatherMedium::echoes(std::uint64_t seed, std::uint64_t pulse_index,
                           std::span<BeamShare> shares, MediumEchoes& out) const {
    out.clear();
    if (weather_.clear_air() || shares.empty()) {
        return;
    }
    if (weather_.fog) {
        fog_profile_.echo(shares, out.fog, out.contributions);
        out.effects.resize(out.contributions.size(), WeatherEffect::fog);
    }
    if (!particles_) {
        return;
    }
    double end_m = 0.0;
    for (const BeamShare& s : shares) {
        end_m = std::max(end_m, s.end_m);
    }
    CounterRng rng(seed, pulse_index, 0, RngStream::weather_particles);
    particles_->sample(rng, end_m, out.particles);
    // A particle lies in the part of the beam still travelling at its range: kept with the
    // probability of that part's weight.
    std::size_t kept = 0;
    for (const Particle& p : out.particles) {
        double travelling = 0.0;
        for (const BeamShare& share : shares) {
            travelling += share.end_m > p.range_m ? share.weight : 0.0;
        }
        if (rng.uniform() < travelling) {
            out.particles[kept++] = p;
        }
    }
    out.particles.resize(kept);
    for (const Particle& p : out.particles) {
        out.contributions.push_back({p.range_m, p.echo_power_w, 0.0});
        out.effects.push_back(particle_effect_);
    }
}

}  // namespace beamtrace
