// The weather's share of one pulse's waveform: the fog's echo and the rain or snow particles in
// the beam (weather.hpp). Built once per survey from the weather and the physics settings; used
// by PulseSimulator for every pulse, from any thread.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "beamtrace/physics/beam_divergence.hpp"
#include "beamtrace/physics/range_equation.hpp"
#include "beamtrace/physics/waveform.hpp"
#include "beamtrace/physics/weather.hpp"
#include "beamtrace/physics/weather_echoes.hpp"

namespace beamtrace {

/// The medium's contributions to one pulse's waveform, with what made each.
struct MediumEchoes {
    /// The fog's leading slabs, summed on the waveform's bins (fog.hpp, SoftTargetProfile);
    /// its other slabs are among the contributions.
    SoftTargetEcho fog;
    std::vector<EchoContribution> contributions;
    std::vector<WeatherEffect> effects;  ///< one per contribution
    /// The particles drawn (their echoes are among the contributions): each takes away its
    /// blocked fraction of the beam behind it.
    std::vector<Particle> particles;
    void clear() {
        fog.clear();
        contributions.clear();
        effects.clear();
        particles.clear();
    }
};

class WeatherMedium {
  public:
    /// `extinction_per_m`: alpha of the whole path (air and weather). Throws ConfigError when
    /// the weather has particles and the beam has no volume (no divergence, no exit diameter).
    WeatherMedium(const WeatherConfig& weather, const RadiometryConfig& radiometry,
                  const BeamConfig& beam, const WaveformConfig& waveform, double extinction_per_m);

    [[nodiscard]] const WeatherConfig& config() const { return weather_; }
    /// Where a share of the beam that meets nothing ends for the medium [m]: beyond it neither
    /// the fog's echo nor any particle's reaches the detection threshold.
    [[nodiscard]] double max_range_m() const { return max_range_m_; }
    /// The medium's echoes of pulse `pulse_index` whose beam shares end at `shares` (sub-ray
    /// weights and hit ranges, misses at max_range_m()), into `out` (cleared first). `shares`
    /// is reordered (sorted by end).
    void echoes(std::uint64_t seed, std::uint64_t pulse_index, std::span<BeamShare> shares,
                MediumEchoes& out) const;

    /// How far each pulse reaches when the echoes are detected in groups, in its sigmas
    /// (detect_echoes_in_groups): kResolvedReachSigmas with rain or snow and no fog, else the
    /// exact kExactReachSigmas.
    [[nodiscard]] double group_reach_sigmas() const { return group_reach_sigmas_; }

    /// What the fog's binned slabs of `echoes` add at an echo's peak at `range_m`: their peak
    /// powers / sigma_m weighted by exp(-((r - range_m) / sigma_m)^2 / 2).
    [[nodiscard]] double binned_fog_share(const MediumEchoes& echoes, double range_m,
                                          double sigma_m) const {
        return fog_profile_.share_at(echoes.fog, range_m, sigma_m);
    }

  private:
    /// The particles' sampler of the whole beam, over the particles' reach.
    [[nodiscard]] ParticleSampler particle_sampler(const WeatherConfig& weather,
                                                   const PrecipitationConfig& p,
                                                   const RadiometryConfig& radiometry,
                                                   const BeamConfig& beam,
                                                   double extinction_per_m) const;

    WeatherConfig weather_;
    SoftTarget fog_;
    SoftTargetSampling fog_sampling_;
    SoftTargetProfile fog_profile_;
    double emitted_power_w_ = 0.0;
    double receiver_gain_m2_ = 0.0;
    double max_range_m_ = 0.0;
    std::optional<ParticleSampler> particles_;
    WeatherEffect particle_effect_ = WeatherEffect::none;
    double group_reach_sigmas_ = kExactReachSigmas;
};

}  // namespace beamtrace
