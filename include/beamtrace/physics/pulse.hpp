// One LiDAR pulse from the sub-ray hits to its returns: the entry point of the physics module.
//
// The caller owns the tracing. Per pulse i of a survey with seed S:
//   1. pose = platform_pose * mount (the TRUE pose)
//   2. axis = pose.apply_direction(pattern_direction)
//      sim.sub_rays(S, i, pose.position_m, axis, origins, dirs)      (jitter + divergence cone
//                                                                     + exit pupil offsets)
//   3. trace origins[j] along every dirs[j]; fill hits[j] (make_sub_ray_hit, or
//      SubRayHit{} for a miss) with the range, cos incidence and material at the hit point
//   4. sim.simulate(S, i, hits, response)                             (range equation, waveform,
//      echoes, return mode, range noise, dropout)
//   5. measured = sim.measured_pose(S, i, t_i, platform_pose, mount)  (georeferencing errors)
//      each response.returns[r] is a point at measured.position_m + range_m * measured axis (the
//      beam's axis, as real sensors report it, placed with the pose the system measured);
//      returns[r].sub_ray names the sub-ray that dominated the echo, so its face/part/label can
//      be attached; intensity is the LAS uint16 of range_equation.hpp.
// Every method is const and pure: call it from any thread, in any order; results depend only on
// (config, seed, pulse index, hits). Reuse one PulseResponse per thread to avoid allocations.
//
// Units: ranges in metres (one-way), powers in watts (peak received power), widths in ns,
// angles in radians.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/quat.hpp"
#include "beamtrace/physics/atmosphere.hpp"
#include "beamtrace/physics/beam_divergence.hpp"
#include "beamtrace/physics/material.hpp"
#include "beamtrace/physics/noise.hpp"
#include "beamtrace/physics/range_equation.hpp"
#include "beamtrace/physics/waveform.hpp"
#include "beamtrace/physics/weather_medium.hpp"

namespace beamtrace {

/// Which detected echoes a pulse reports.
enum class ReturnMode : std::uint8_t {
    first,      ///< the nearest echo only
    last,       ///< the farthest echo only
    strongest,  ///< the echo of largest amplitude only
    all,        ///< every echo, nearest first, up to max_returns (the farther ones are lost)
};

/// "first", "last", "strongest", "all".
[[nodiscard]] std::string_view to_string(ReturnMode mode);
/// The mode named `name`; throws ConfigError listing the choices.
[[nodiscard]] ReturnMode parse_return_mode(std::string_view name);

/// Everything the physics of one pulse needs. Defaults: a 1064 nm, 1 kW, 5 cm aperture sensor,
/// clear air (23 km), an ideal ray (no divergence), no noise, a 4 ns pulse sampled at 0.5 ns,
/// all returns up to 5.
struct PhysicsConfig {
    RadiometryConfig radiometry;
    AtmosphereConfig atmosphere;
    BeamConfig beam;
    NoiseConfig noise;
    WaveformConfig waveform;
    /// The reflectance of the range equation's L(i) (material.hpp): the energy-conserving
    /// normalised Phong lobe, or the seed's phenomenological one.
    Brdf brdf = Brdf::normalized_phong;
    ReturnMode return_mode = ReturnMode::all;
    int max_returns = 5;         ///< 1..15 (LAS 1.4 allows 15 returns per pulse)
    bool keep_waveform = false;  ///< keep the sampled waveform in PulseResponse::waveform
    /// Fog, rain or snow and wet surfaces (weather.hpp; the survey file's `weather:` block);
    /// nullopt: clear air.
    std::optional<WeatherConfig> weather;

    /// Every problem of every part; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// What one sub-ray saw. A default-constructed one is a miss.
struct SubRayHit {
    double range_m = std::numeric_limits<double>::infinity();  ///< one-way; not finite: miss
    double cos_incidence = 1.0;       ///< |n . d| of the surface normal and the sub-ray
    double albedo = 0.5;              ///< reflectance at the hit (albedo(material, frame, point))
    double specular_weight = 0.0;     ///< s of the material
    double specular_exponent = 10.0;  ///< n of the material
};

/// |n . d| / |n| for a normal of length `normal_length` (0: a degenerate face, 0), at most 1.
[[nodiscard]] inline double cos_incidence_of(const Vec3d& normal, double normal_length,
                                             const Vec3d& direction) {
    return normal_length > 0 ? std::min(1.0, std::abs(dot(normal, direction)) / normal_length)
                             : 0.0;
}

/// The SubRayHit of a sub-ray along unit `direction` hitting `material` at `point_m`, `range_m`
/// away, where the surface normal is `normal` (either orientation; need not be unit). The
/// material's pattern is evaluated at `point_m` on the surface `frame` (the hit part's).
[[nodiscard]] SubRayHit make_sub_ray_hit(const Material& material, const PatternFrame& frame,
                                         double range_m, const Vec3d& point_m, const Vec3d& normal,
                                         const Vec3d& direction);

/// The same on a solid (the pattern in scene coordinates).
[[nodiscard]] SubRayHit make_sub_ray_hit(const Material& material, double range_m,
                                         const Vec3d& point_m, const Vec3d& normal,
                                         const Vec3d& direction);

/// One weighted sample of the beam: a sub-ray, or in an edge cell the sub-ray or one of its
/// probes (beam_divergence.hpp), with its share of the pulse energy and the per-axis spread of
/// the footprint it stands for (beam units, the echo's stretch: echo_sigma_ns).
struct BeamSample {
    SubRayHit hit;
    double weight = 1.0;
    double cell_sigma = 0.0;
};

struct PulseReturn {
    double range_m = 0.0;            ///< one-way range with range noise
    double amplitude_w = 0.0;        ///< peak power of the echo
    double power_w = 0.0;            ///< equivalent power (see waveform.hpp), what intensity maps
    double echo_width_ns = 0.0;      ///< FWHM of the echo
    std::uint16_t intensity = 0;     ///< LAS intensity of power_w (range_equation.hpp)
    std::uint8_t return_number = 1;  ///< 1-based, in range order among the reported returns
    std::uint8_t number_of_returns = 1;
    std::uint32_t sub_ray = 0;  ///< index of the sub-ray (simulate_samples: sample) that
                                ///< contributed most among the beam's samples
    /// What made the echo when the weather's medium contributed more to it than any sample of
    /// the beam (its point is the medium's, not sub_ray's target); none otherwise.
    WeatherEffect weather = WeatherEffect::none;
};

struct PulseResponse {
    bool dropped = false;                 ///< lost to a random dropout (then no returns)
    std::vector<PulseReturn> returns;     ///< what the pulse reports, nearest first
    std::vector<Echo> echoes;             ///< every echo detected, before the return mode
    Waveform waveform;                    ///< the sampled waveform (when keep_waveform)
    std::vector<double> sub_ray_power_w;  ///< received power of every sub-ray or sample (0: miss)
    std::vector<double> sigma_ns;         ///< working space: every sample's echo width
    std::vector<EchoContribution> contributions;  ///< the sub-rays with power > 0
    std::vector<BeamSample> samples;              ///< simulate()'s working space
    MediumEchoes medium;                          ///< the weather's echoes (working space)
    std::vector<BeamShare> shares;                ///< working space
};

/// The physics of a configuration, with the beam pattern and constants precomputed.
class PulseSimulator {
  public:
    /// Throws ConfigError listing every problem of `config`.
    explicit PulseSimulator(PhysicsConfig config);

    [[nodiscard]] const PhysicsConfig& config() const { return config_; }
    /// The sub-ray pattern (its size is the number of sub-rays per pulse).
    [[nodiscard]] std::span<const SubRayOffset> pattern() const { return pattern_; }
    [[nodiscard]] std::size_t sub_ray_count() const { return pattern_.size(); }
    /// The extinction coefficient in use [1/m].
    [[nodiscard]] double extinction_per_m() const { return alpha_per_m_; }

    /// The sensor pose the system records for pulse `pulse_index` fired at `time_s` from the
    /// true `platform` pose with the sensor-to-platform `mount`: the georeferencing errors of
    /// config().noise.georeferencing applied (georeferencing.hpp). One pulse at a time (it
    /// evaluates the Gauss-Markov nodes afresh); blocks use platform_errors() with a scratch.
    [[nodiscard]] Pose measured_pose(std::uint64_t seed, std::uint64_t pulse_index, double time_s,
                                     const Pose& platform, const Pose& mount) const;
    /// The world directions of the pulse's sub-rays around the unit beam `axis` (jittered);
    /// out.size() must equal sub_ray_count(). out[j] belongs to pattern()[j].
    void sub_ray_directions(std::uint64_t seed, std::uint64_t pulse_index, const Vec3d& axis,
                            std::span<Vec3d> out) const;
    /// Like sub_ray_directions, with the start points of the sub-rays in the exit pupil
    /// (beam_divergence.hpp) around `origin` into `origins` (all equal to `origin` when
    /// exit_diameter_m is 0). Both spans must have sub_ray_count() entries.
    void sub_rays(std::uint64_t seed, std::uint64_t pulse_index, const Vec3d& origin,
                  const Vec3d& axis, std::span<Vec3d> origins, std::span<Vec3d> dirs) const;
    /// The echo width (sigma, ns) of a sub-ray hit: its footprint cell, of per-axis spread
    /// sqrt(cell_variance) W(R) on a surface at incidence i (tan i capped at 89.5 deg), spans
    /// sigma_R = tan i sqrt(cell_variance) W(R) in range, so sigma^2 = sigma_p^2 + (2 sigma_R/c)^2.
    [[nodiscard]] double echo_sigma_ns(const SubRayHit& hit) const;
    /// echo_sigma_ns of every sample into `out` (resized): bit for bit, four at a time with AVX2.
    void echo_sigmas(std::span<const BeamSample> samples, std::vector<double>& out) const;
    /// The received power of one sub-ray hit with pattern weight `weight` [W], with the
    /// configured BRDF's monostatic L(i) and the two-way transmission exp(-2 alpha R) (by
    /// beamtrace's exp, within an ulp of std::exp's: the same bits in lanes).
    [[nodiscard]] double sub_ray_power_w(const SubRayHit& hit, double weight) const;
    /// The returns of pulse `pulse_index` whose sub-rays saw `hits` (hits.size() must equal
    /// sub_ray_count(); hits[j] belongs to pattern()[j]), each sub-ray filling its cell.
    void simulate(std::uint64_t seed, std::uint64_t pulse_index, std::span<const SubRayHit> hits,
                  PulseResponse& out) const;
    /// The same from weighted samples of the beam (their weights sum to 1); returns[r].sub_ray
    /// is then the index of the sample that contributed most to the echo. `samples` may be
    /// out.samples: only the other fields of `out` are written.
    void simulate_samples(std::uint64_t seed, std::uint64_t pulse_index,
                          std::span<const BeamSample> samples, PulseResponse& out) const;

    // Edge cells (beam_divergence.hpp): targets smaller than a sub-ray's cell.
    /// Probe rays per edge cell: edge_samples^2, or 0 (a single ray, or edge_samples 0).
    [[nodiscard]] std::size_t probes_per_cell() const { return probes_per_cell_; }
    /// The cells whose sub-ray met another target than one of its neighbours' into `out`, in
    /// order: target[j] names what sub-ray j met (e.g. the part; -1 for a miss). Empty when
    /// every sub-ray met the same target or probes_per_cell() is 0.
    void edge_cells(std::span<const std::int64_t> target, std::vector<std::uint32_t>& out) const;
    /// The probe rays of `cell` into `origins` and `dirs` (probes_per_cell() entries each):
    /// `origin` and `axis` are those of the pulse's centre sub-ray (pattern()[0], on the beam's
    /// jittered axis), as sub_rays() made them.
    void probe_rays(const Vec3d& origin, const Vec3d& axis, std::size_t cell,
                    std::span<Vec3d> origins, std::span<Vec3d> dirs) const;
    /// The BeamSample of a sub-ray filling cell j, or of one of the probe_rays of an edge cell
    /// (sharing its energy with the sub-ray and the cell's other probes).
    [[nodiscard]] BeamSample cell_sample(const SubRayHit& hit, std::size_t cell) const {
        return {hit, pattern_[cell].weight, cell_sigma_};
    }
    [[nodiscard]] BeamSample edge_sample(const SubRayHit& hit, std::size_t cell) const;
    /// cell_sample(sample.hit, cell) in place: the weight and spread of cell `cell`.
    void set_cell_sample(BeamSample& sample, std::size_t cell) const {
        sample.weight = pattern_[cell].weight;
        sample.cell_sigma = cell_sigma_;
    }

  private:
    PhysicsConfig config_;
    std::vector<SubRayOffset> pattern_;
    std::vector<Vec3d> beam_frame_;    ///< pattern_ as unit vectors in the beam frame
    std::vector<Vec3d> beam_origins_;  ///< start offsets in the beam frame (exit pupil)
    double cell_sigma_ = 0.0;          ///< sqrt(cell_variance(pattern_)), beam units
    double sigma_p_ns_ = 0.0;          ///< the pulse's sigma (its FWHM / 2 sqrt(2 ln 2))
    std::size_t probes_per_cell_ = 0;
    std::vector<Vec3d> probe_frame_;    ///< cell_probe_pattern as unit vectors (beam frame)
    std::vector<Vec3d> probe_origins_;  ///< their start offsets in the beam frame
    std::vector<std::vector<std::uint32_t>> neighbours_;  ///< cell_neighbours

    /// echo_sigma_ns of a footprint of per-axis spread `cell_sigma` (beam units).
    [[nodiscard]] double echo_sigma_ns(const SubRayHit& hit, double cell_sigma) const;
    /// -2 alpha R: the exponent of the two-way transmission over `range_m`.
    [[nodiscard]] double transmission_exponent(double range_m) const;
    /// sub_ray_power_w with the two-way `transmission` given.
    [[nodiscard]] double sub_ray_power_w(const SubRayHit& hit, double weight,
                                         double transmission) const;
    /// sub_ray_power_w of every sample into out[0, samples.size()), the transmissions in lanes.
    void sub_ray_powers(std::span<const BeamSample> samples, std::span<double> out) const;
    double alpha_per_m_ = 0.0;
    std::optional<WeatherMedium> medium_;  ///< with weather in the air

    /// The samples' powers (out.sub_ray_power_w) and, for those of positive power, their echoes
    /// (out.contributions), the weather's after them.
    void sample_contributions(std::uint64_t seed, std::uint64_t pulse_index,
                              std::span<const BeamSample> samples, PulseResponse& out) const;
    /// The weather's echoes of the pulse into out.medium, and the particles' shadows taken off
    /// the samples' powers (out.sub_ray_power_w) behind them.
    void add_medium(std::uint64_t seed, std::uint64_t pulse_index,
                    std::span<const BeamSample> samples, PulseResponse& out) const;
    /// The weather effect that made the echo at `range_m`, if the medium dominates it.
    [[nodiscard]] WeatherEffect medium_dominates(const PulseResponse& out, double sample_share,
                                                 double range_m) const;
};

/// One-shot convenience: PulseSimulator(config).simulate(...). Prefer the class in loops.
[[nodiscard]] PulseResponse simulate_pulse(const PhysicsConfig& config, std::uint64_t seed,
                                           std::uint64_t pulse_index,
                                           std::span<const SubRayHit> hits);

}  // namespace beamtrace
