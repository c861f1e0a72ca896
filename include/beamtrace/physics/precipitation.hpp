// Rain and snow: particles inside the beam that extinguish it, shadow what lies behind them and
// return echoes of their own.
//
// Drop sizes follow an exponential distribution N(D) = N0 exp(-Lambda D) [1/(m^3 mm)], D the
// (melted) diameter in mm, for a precipitation rate R in mm/h:
//   rain, Marshall and Palmer (J. Meteor. 5, 1948):  N0 = 8000,             Lambda = 4.1 R^-0.21
//   snow, Gunn and Marshall (J. Meteor. 15, 1958):   N0 = 3800 R^-0.87,     Lambda = 2.55 R^-0.48
// Particles are large against the wavelength, so each removes twice its geometric cross-section
// from the beam (extinction efficiency 2): alpha = 2 * integral (pi D^2 / 4) N(D) dD
// = pi N0 / Lambda^3 (in 1/m once mm^2 are converted to m^2).
//
// A particle of diameter D at range r in a beam cell (a sub-ray's share: energy fraction w, area
// A(r) = a_f pi (w_0 + r theta / 2)^2, a_f its share of the beam's area) intercepts the fraction
// f = min(1, (pi D^2 / 4) / A(r)) of the cell's power and scatters it back as a Lambertian sphere
// of albedo a, whose radiant intensity towards the sensor is 2/3 of a facing disc's (backscatter
// efficiency Q_b = 8 a / 3). Its echo's peak power, a pulse like a hard target's:
//   P = (2 / 3) (a / pi) f w P_t eta A_r xi(r) exp(-2 alpha r) / r^2
// (xi the receiver's overlap, fog.hpp).
// The particles whose echo reaches a floor power are drawn per pulse and cell from the counter
// RNG: a Poisson number with mean mu = integral A(r) n(r) dr up to the cell's end (its hard
// target), n(r) = (N0 / Lambda) exp(-Lambda D_min(r)) the density of particles at least D_min(r)
// large, then each one's range from that density and its diameter D_min(r) + Exp(Lambda). The
// smaller particles act through alpha only.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/rng.hpp"
#include "beamtrace/physics/fog.hpp"

namespace beamtrace {

enum class PrecipitationKind : std::uint8_t { rain, snow };
/// "rain", "snow".
[[nodiscard]] std::string_view to_string(PrecipitationKind kind);
/// The kind named `name`; throws ConfigError listing the choices.
[[nodiscard]] PrecipitationKind parse_precipitation_kind(std::string_view name);

/// N(D) = n0 exp(-slope D), D in mm.
struct DropSizeDistribution {
    double n0_per_m3_mm = 0.0;
    double slope_per_mm = 1.0;
};

/// The distribution of `kind` at `rate_mm_h` (> 0; the melted-water rate for snow).
[[nodiscard]] DropSizeDistribution drop_size_distribution(PrecipitationKind kind, double rate_mm_h);
/// Particles per cubic metre: n0 / slope.
[[nodiscard]] double number_density_per_m3(const DropSizeDistribution& dsd);
/// alpha = pi n0 / slope^3 (converted to 1/m).
[[nodiscard]] double extinction_per_m(const DropSizeDistribution& dsd);

/// Albedo of a particle when the survey file gives none: 0.02 for water (the Fresnel reflectance
/// of water at normal incidence, ((n - 1) / (n + 1))^2 with n = 1.33), 0.8 for snow (fresh snow
/// in the near infrared).
[[nodiscard]] double default_particle_albedo(PrecipitationKind kind);

/// The beam a pulse's particles are drawn in.
struct ParticleBeam {
    double exit_radius_m = 0.0;     ///< w_0, the beam's radius where it leaves the sensor
    double half_angle_rad = 0.0;    ///< theta / 2, the beam's half divergence
    double emitted_power_w = 0.0;   ///< P_t of the whole pulse
    double receiver_gain_m2 = 0.0;  ///< eta A_r
    double extinction_per_m = 0.0;  ///< alpha of the whole path
    double floor_w = 0.0;           ///< the weakest particle echo drawn (> 0)
    double start_m = 0.0;           ///< no particle closer than this (the sensor's blind zone), > 0
    /// The receiver's view of the beam (fog.hpp): a particle's echo is scaled by xi(r).
    OverlapConfig overlap{0.0, 1e-9};
    double max_range_m = 0.0;  ///< no particle beyond this
};

/// One sub-ray's share of the beam.
struct ParticleCell {
    double energy_fraction = 1.0;  ///< w
    double area_fraction = 1.0;    ///< a_f
};

/// A drawn particle.
struct Particle {
    double range_m = 0.0;
    double diameter_m = 0.0;
    double echo_power_w = 0.0;      ///< P of the header, extinction included
    double blocked_fraction = 0.0;  ///< f: the share of the cell's power it takes away
};

/// Draws the particles of one beam cell; built once per survey and cell, used by any thread.
class ParticleSampler {
  public:
    /// Tabulates mu(r) on `table_size` ranges from beam.start_m to beam.max_range_m.
    ParticleSampler(const DropSizeDistribution& dsd, double albedo, const ParticleBeam& beam,
                    const ParticleCell& cell, std::size_t table_size = 4096);

    /// The least diameter [m] whose echo at `range_m` reaches the floor (+inf: none does).
    [[nodiscard]] double least_diameter_m(double range_m) const;
    /// The echo's peak power [W] of a particle of `diameter_m` at `range_m`.
    [[nodiscard]] double echo_power_w(double diameter_m, double range_m) const;
    /// The cell's area A(r) [m^2].
    [[nodiscard]] double cell_area_m2(double range_m) const;
    /// Mean number of particles drawn up to `end_m` (the table's interpolation of mu).
    [[nodiscard]] double expected_count(double end_m) const;
    /// Appends the particles between start_m and `end_m` to `out`, in the order drawn (not
    /// sorted), with `rng`'s numbers.
    void sample(CounterRng& rng, double end_m, std::vector<Particle>& out) const;

  private:
    /// What a particle's echo needs of its range: A(r), xi(r) and exp(-2 alpha r).
    struct AtRange {
        double range_m, area_m2, overlap, transmission;
    };
    [[nodiscard]] AtRange at_range(double range_m) const;
    [[nodiscard]] double echo_power_w(double diameter_m, const AtRange& at) const;
    [[nodiscard]] double least_diameter_m(const AtRange& at) const;
    [[nodiscard]] double density_per_m(double range_m) const;  ///< A(r) n(r)
    [[nodiscard]] double range_at(double count) const;         ///< inverse of mu
    /// std::upper_bound(cumulative_, count)'s index, from the guide.
    [[nodiscard]] std::size_t upper_bound_of(double count) const;

    DropSizeDistribution dsd_;
    double albedo_;
    ParticleBeam beam_;
    ParticleCell cell_;
    double tan_half_angle_;  ///< tan(beam_.half_angle_rad)
    double step_m_ = 0.0;
    std::vector<double> cumulative_;  ///< mu at start_m + k * step_m_
    /// guide_[j]: upper_bound of j / guide_per_count_ in cumulative_ (where range_at starts).
    std::vector<std::size_t> guide_;
    double guide_per_count_ = 0.0;  ///< guide entries per unit of mu
};

/// A Poisson-distributed count of mean `mean` from `rng` (inversion; means above 200 are drawn
/// as sums of smaller ones).
[[nodiscard]] std::uint64_t poisson_count(CounterRng& rng, double mean);

}  // namespace beamtrace
