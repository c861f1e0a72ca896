#include "beamtrace/physics/pulse.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/name_table.hpp"
#include "beamtrace/physics/weather_echoes.hpp"
#include "physics/detail/fast_exp.hpp"

namespace beamtrace {

namespace {

const BinnedEcho kNoBinnedEcho{};

constexpr NameTable<ReturnMode, 4> kReturnModes{"return mode",
                                                {{{ReturnMode::first, "first"},
                                                  {ReturnMode::last, "last"},
                                                  {ReturnMode::strongest, "strongest"},
                                                  {ReturnMode::all, "all"}}}};

/// The echoes a pulse reports in `mode`: [first, second) of `echoes` (not empty).
std::pair<std::size_t, std::size_t> reported_echoes(const std::vector<Echo>& echoes,
                                                    ReturnMode mode, std::size_t max_returns) {
    switch (mode) {
        case ReturnMode::first:
            return {0, 1};
        case ReturnMode::last:
            return {echoes.size() - 1, echoes.size()};
        case ReturnMode::strongest: {
            std::size_t best = 0;
            for (std::size_t e = 1; e < echoes.size(); ++e) {
                if (echoes[e].amplitude_w > echoes[best].amplitude_w) {
                    best = e;
                }
            }
            return {best, best + 1};
        }
        case ReturnMode::all:
            break;
    }
    return {0, std::min(echoes.size(), max_returns)};
}

/// The sample whose (stretched) echo adds most at an echo's peak at `range_m`, and how much
/// (its power times the pulse's shape there, per metre); `contributions` starts with one entry
/// per sample of positive power, in order.
std::pair<std::uint32_t, double> dominant_sample(std::span<const BeamSample> samples,
                                                 const std::vector<double>& powers,
                                                 const std::vector<EchoContribution>& contributions,
                                                 double range_m) {
    double best = -1.0;
    std::uint32_t best_j = 0;
    for (std::size_t j = 0, c = 0; j < powers.size(); ++j) {
        if (powers[j] > 0) {
            const double sigma_m = contributions[c++].sigma_ns / round_trip_ns_per_m();
            // The share is at most powers[j] / sigma_m (exp <= 1, and the product rounds no
            // higher): a sample that cannot pass the best needs no exp.
            const double bound = powers[j] / sigma_m;
            if (!(bound > best)) {
                continue;
            }
            const double d = (samples[j].hit.range_m - range_m) / sigma_m;
            const double share = bound * std::exp(-0.5 * d * d);
            if (share > best) {
                best = share;
                best_j = static_cast<std::uint32_t>(j);
            }
        }
    }
    return {best_j, best};
}

}  // namespace

std::string_view to_string(ReturnMode mode) {
    return kReturnModes.to_string(mode);
}

ReturnMode parse_return_mode(std::string_view name) {
    return kReturnModes.parse(name);
}

std::vector<std::string> PhysicsConfig::validate() const {
    std::vector<std::string> p;
    for (auto&& part :
         {radiometry.validate(), atmosphere.validate(), beam.validate(), noise.validate(),
          waveform.validate(), weather ? weather->validate() : std::vector<std::string>{}}) {
        p.insert(p.end(), part.begin(), part.end());
    }
    if (max_returns < 1 || max_returns > 15) {
        p.emplace_back("max_returns must be in [1, 15]");
    }
    return p;
}

SubRayHit make_sub_ray_hit(const Material& material, const PatternFrame& frame, double range_m,
                           const Vec3d& point_m, const Vec3d& normal, const Vec3d& direction) {
    SubRayHit h;
    h.range_m = range_m;
    h.cos_incidence = cos_incidence_of(normal, length(normal), direction);
    h.albedo = albedo(material, frame, point_m);
    h.specular_weight = material.specular_weight;
    h.specular_exponent = material.specular_exponent;
    return h;
}

SubRayHit make_sub_ray_hit(const Material& material, double range_m, const Vec3d& point_m,
                           const Vec3d& normal, const Vec3d& direction) {
    return make_sub_ray_hit(material, PatternFrame{}, range_m, point_m, normal, direction);
}

PulseSimulator::PulseSimulator(PhysicsConfig config) : config_(std::move(config)) {
    const auto problems = config_.validate();
    if (!problems.empty()) {
        std::string msg = "invalid physics settings:";
        for (const auto& s : problems) {
            msg += "\n  " + s;
        }
        throw ConfigError(msg);
    }
    pattern_ = beam_pattern(config_.beam);
    beam_frame_ = beam_frame_directions(pattern_);
    beam_origins_ = beam_frame_origins(config_.beam, pattern_);
    cell_sigma_ = std::sqrt(cell_variance(pattern_));
    sigma_p_ns_ = config_.waveform.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    const std::vector<SubRayOffset> probes = cell_probe_pattern(config_.beam);
    if (!probes.empty() && pattern_.size() > 1) {
        assert(pattern_[0].radius == 0.0);  // probe_rays starts from the centre sub-ray
        probes_per_cell_ = probes.size() / pattern_.size();
        probe_frame_ = beam_frame_directions(probes);
        probe_origins_ = beam_frame_origins(config_.beam, probes);
        neighbours_ = cell_neighbours(config_.beam);
    }
    alpha_per_m_ =
        beamtrace::extinction_per_m(config_.atmosphere, config_.radiometry.wavelength_nm);
    if (config_.weather) {
        alpha_per_m_ += weather_extinction_per_m(*config_.weather);
        if (!config_.weather->clear_air()) {
            medium_.emplace(*config_.weather, config_.radiometry, config_.beam, config_.waveform,
                            alpha_per_m_);
        }
    }
}

Pose PulseSimulator::measured_pose(std::uint64_t seed, std::uint64_t pulse_index, double time_s,
                                   const Pose& platform, const Pose& mount) const {
    const GeoreferencingConfig& g = config_.noise.georeferencing;
    PoseError e;
    PlatformErrorScratch scratch;
    platform_errors(g, seed, pulse_index, {&time_s, 1}, {&e, 1}, scratch);
    return measured_sensor_pose(g, platform, mount, e);
}

void PulseSimulator::sub_ray_directions(std::uint64_t seed, std::uint64_t pulse_index,
                                        const Vec3d& axis, std::span<Vec3d> out) const {
    const Vec3d jittered = jitter_direction(config_.noise, seed, pulse_index, axis);
    beamtrace::sub_ray_directions(jittered, beam_frame_, out);
}

void PulseSimulator::sub_rays(std::uint64_t seed, std::uint64_t pulse_index, const Vec3d& origin,
                              const Vec3d& axis, std::span<Vec3d> origins,
                              std::span<Vec3d> dirs) const {
    assert(origins.size() == pattern_.size());
    const Vec3d jittered = jitter_direction(config_.noise, seed, pulse_index, axis);
    beamtrace::sub_ray_directions(jittered, beam_frame_, dirs);
    if (config_.beam.exit_diameter_m > 0) {
        beamtrace::sub_ray_origins(origin, jittered, beam_origins_, origins);
    } else {
        std::fill(origins.begin(), origins.end(), origin);  // bit for bit the sensor's origin
    }
}

double PulseSimulator::echo_sigma_ns(const SubRayHit& hit) const {
    return echo_sigma_ns(hit, cell_sigma_);
}

namespace {
constexpr double kMinCos = 0.008726535498373935;  // cos 89.5 deg: tan i at most 114.6
}  // namespace

// Inline (only this file calls it): sample_contributions' loop of widths keeps the square roots
// of several samples in flight.
inline double PulseSimulator::echo_sigma_ns(const SubRayHit& hit, double cell_sigma) const {
    const double sigma_p = sigma_p_ns_;
    const double w_m = footprint_radius_m(config_.beam, hit.range_m);
    if (!(w_m > 0) || !(cell_sigma > 0)) {
        return sigma_p;
    }
    const double c = std::clamp(hit.cos_incidence, kMinCos, 1.0);
    const double tan_i = std::sqrt((1.0 - c) * (1.0 + c)) / c;
    const double spread_ns = tan_i * cell_sigma * w_m * round_trip_ns_per_m();
    return std::sqrt(sigma_p * sigma_p + spread_ns * spread_ns);
}

namespace {

#if defined(__x86_64__) && defined(__GNUC__)
/// echo_sigma_ns of the samples of a beam without exit diameter (footprint radius |R theta / 2|),
/// four at a time (AVX2, no FMA: every product and sum rounded alone; sqrt and division round
/// alike in lanes): the same operations in the same order. The last four end at n (they
/// overlap the four before them: each lane's result alone, the same again). Returns how many it
/// did (n, or 0 where n < 4).
__attribute__((target("avx2"))) std::size_t narrow_echo_sigmas_avx2(const BeamSample* samples,
                                                                    std::size_t n,
                                                                    double divergence_rad,
                                                                    double sigma_p, double* out) {
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
    const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffff));
    const __m256d sp = _mm256_set1_pd(sigma_p), min_cos = _mm256_set1_pd(kMinCos);
    for (std::size_t next = 0; next < n && n >= 4; next += 4) {
        const std::size_t j = std::min(next, n - 4);
        const BeamSample* s = samples + j;
        const __m256d r =
            _mm256_setr_pd(s[0].hit.range_m, s[1].hit.range_m, s[2].hit.range_m, s[3].hit.range_m);
        const __m256d cos_i = _mm256_setr_pd(s[0].hit.cos_incidence, s[1].hit.cos_incidence,
                                             s[2].hit.cos_incidence, s[3].hit.cos_incidence);
        const __m256d cell =
            _mm256_setr_pd(s[0].cell_sigma, s[1].cell_sigma, s[2].cell_sigma, s[3].cell_sigma);
        const __m256d w_m = _mm256_and_pd(
            _mm256_div_pd(_mm256_mul_pd(r, _mm256_set1_pd(divergence_rad)), _mm256_set1_pd(2.0)),
            abs_mask);
        // std::clamp(cos_i, kMinCos, 1): NaN stays NaN (both tests false).
        __m256d c = _mm256_blendv_pd(cos_i, one, _mm256_cmp_pd(one, cos_i, _CMP_LT_OQ));
        c = _mm256_blendv_pd(c, min_cos, _mm256_cmp_pd(cos_i, min_cos, _CMP_LT_OQ));
        const __m256d tan_i = _mm256_div_pd(
            _mm256_sqrt_pd(_mm256_mul_pd(_mm256_sub_pd(one, c), _mm256_add_pd(one, c))), c);
        const __m256d spread = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(tan_i, cell), w_m),
                                             _mm256_set1_pd(round_trip_ns_per_m()));
        const __m256d sigma =
            _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(sp, sp), _mm256_mul_pd(spread, spread)));
        // sigma_p where !(w_m > 0) || !(cell > 0).
        const __m256d wide = _mm256_and_pd(_mm256_cmp_pd(w_m, zero, _CMP_GT_OQ),
                                           _mm256_cmp_pd(cell, zero, _CMP_GT_OQ));
        _mm256_storeu_pd(out + j, _mm256_blendv_pd(sp, sigma, wide));
    }
    return n >= 4 ? n : 0;
}

/// What sub_ray_power_w reads of the configuration: the emitted peak power and the constant
/// factors of received_power_w, each as it computes them.
struct PowerFactors {
    double peak_w, aperture_m2, efficiency;
};

/// sub_ray_power_w of samples [0, n) four at a time (AVX2, no FMA: every product and quotient
/// rounded alone, in received_power_w's order), for the fours whose samples have no specular
/// weight: the reflectance of either BRDF is then cos_i where cos_i > 0 (1 cos_i, 0 + 1 cos_i),
/// else 0. transmission[j] is sample j's two-way transmission. The last four end at n (they
/// overlap the four before them: each lane's result alone, the same again). Returns how many it
/// did: the samples before the first four with a specular weight, or n (0 where n < 4).
__attribute__((target("avx2"))) std::size_t matte_powers_avx2(const BeamSample* samples,
                                                              std::size_t n,
                                                              const double* transmission,
                                                              const PowerFactors& k, double* out) {
    const __m256d zero = _mm256_setzero_pd(),
                  inf = _mm256_set1_pd(std::numeric_limits<double>::infinity());
    const __m256d peak = _mm256_set1_pd(k.peak_w), area = _mm256_set1_pd(k.aperture_m2);
    const __m256d pi = _mm256_set1_pd(std::numbers::pi), eff = _mm256_set1_pd(k.efficiency);
    for (std::size_t next = 0; next < n && n >= 4; next += 4) {
        const std::size_t j = std::min(next, n - 4);
        const BeamSample* s = samples + j;
        const __m256d spec = _mm256_setr_pd(s[0].hit.specular_weight, s[1].hit.specular_weight,
                                            s[2].hit.specular_weight, s[3].hit.specular_weight);
        if (_mm256_movemask_pd(_mm256_cmp_pd(spec, zero, _CMP_EQ_OQ)) != 0xf) {
            return j;
        }
        const __m256d r =
            _mm256_setr_pd(s[0].hit.range_m, s[1].hit.range_m, s[2].hit.range_m, s[3].hit.range_m);
        const __m256d cos_i = _mm256_setr_pd(s[0].hit.cos_incidence, s[1].hit.cos_incidence,
                                             s[2].hit.cos_incidence, s[3].hit.cos_incidence);
        const __m256d a =
            _mm256_setr_pd(s[0].hit.albedo, s[1].hit.albedo, s[2].hit.albedo, s[3].hit.albedo);
        const __m256d w = _mm256_setr_pd(s[0].weight, s[1].weight, s[2].weight, s[3].weight);
        const __m256d l = _mm256_and_pd(_mm256_cmp_pd(cos_i, zero, _CMP_GT_OQ), cos_i);
        const __m256d emitted = _mm256_mul_pd(peak, w);
        const __m256d num = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(emitted, a), l), area);
        const __m256d q = _mm256_div_pd(num, _mm256_mul_pd(_mm256_mul_pd(pi, r), r));
        const __m256d p = _mm256_mul_pd(_mm256_mul_pd(q, eff), _mm256_loadu_pd(transmission + j));
        // powered: finite and positive (NaN fails both compares).
        const __m256d lit =
            _mm256_and_pd(_mm256_cmp_pd(r, zero, _CMP_GT_OQ), _mm256_cmp_pd(r, inf, _CMP_LT_OQ));
        _mm256_storeu_pd(out + j, _mm256_and_pd(lit, p));
    }
    return n >= 4 ? n : 0;
}
#endif

}  // namespace

namespace {

/// True when a hit at `range_m` receives power (a finite, positive range).
bool powered(double range_m) {
    return std::isfinite(range_m) && range_m > 0;
}

}  // namespace

double PulseSimulator::transmission_exponent(double range_m) const {
    return two_way_transmission_exponent(alpha_per_m_, range_m);  // its exp: fast_exp's
}

double PulseSimulator::sub_ray_power_w(const SubRayHit& hit, double weight,
                                       double transmission) const {
    if (!powered(hit.range_m)) {
        return 0.0;
    }
    const double l = monostatic_reflectance(config_.brdf, hit.cos_incidence, hit.specular_weight,
                                            hit.specular_exponent);
    return received_power_w(config_.radiometry, config_.radiometry.peak_power_w * weight,
                            hit.albedo, l, hit.range_m, transmission);
}

double PulseSimulator::sub_ray_power_w(const SubRayHit& hit, double weight) const {
    return sub_ray_power_w(hit, weight, detail::fast_exp(transmission_exponent(hit.range_m)));
}

void PulseSimulator::sub_ray_powers(std::span<const BeamSample> samples,
                                    std::span<double> out) const {
    // The transmissions of a chunk of samples in lanes, then their powers: sub_ray_power_w's
    // bits (fast_exp's in every lane).
    constexpr std::size_t kChunk = 32;
    double t[kChunk];
    for (std::size_t j0 = 0; j0 < samples.size(); j0 += kChunk) {
        const std::size_t m = std::min(kChunk, samples.size() - j0);
        for (std::size_t i = 0; i < m; ++i) {
            const double r = samples[j0 + i].hit.range_m;
            t[i] = powered(r) ? transmission_exponent(r) : 0.0;  // no power: any exponent
        }
        detail::fast_exp_lanes(t, t, m);
        std::size_t i = 0;
#if defined(__x86_64__) && defined(__GNUC__)
        if (__builtin_cpu_supports("avx2")) {
            const RadiometryConfig& rc = config_.radiometry;
            i = matte_powers_avx2(samples.data() + j0, m, t,
                                  {rc.peak_power_w, aperture_area_m2(rc), rc.system_efficiency},
                                  out.data() + j0);
        }
#endif
        for (; i < m; ++i) {
            out[j0 + i] = sub_ray_power_w(samples[j0 + i].hit, samples[j0 + i].weight, t[i]);
        }
    }
}

void PulseSimulator::echo_sigmas(std::span<const BeamSample> samples,
                                 std::vector<double>& out) const {
    out.resize(samples.size());
    std::size_t j = 0;
#if defined(__x86_64__) && defined(__GNUC__)
    // With an exit diameter the footprint takes hypot: one call after the other.
    if (config_.beam.exit_diameter_m == 0 && __builtin_cpu_supports("avx2")) {
        j = narrow_echo_sigmas_avx2(samples.data(), samples.size(), config_.beam.divergence_rad,
                                    sigma_p_ns_, out.data());
    }
#endif
    for (; j < samples.size(); ++j) {
        out[j] = echo_sigma_ns(samples[j].hit, samples[j].cell_sigma);
    }
}

void PulseSimulator::simulate(std::uint64_t seed, std::uint64_t pulse_index,
                              std::span<const SubRayHit> hits, PulseResponse& out) const {
    assert(hits.size() == pattern_.size());
    out.samples.clear();
    const std::size_t n = std::min(hits.size(), pattern_.size());
    for (std::size_t j = 0; j < n; ++j) {
        out.samples.push_back(cell_sample(hits[j], j));
    }
    simulate_samples(seed, pulse_index, out.samples, out);
}

BeamSample PulseSimulator::edge_sample(const SubRayHit& hit, std::size_t cell) const {
    // The sub-ray and its P probes share the cell; each probe's sub-cell is 1/sqrt(P) the
    // cell's size along each axis, and so is the spread of its echo.
    const auto p = static_cast<double>(probes_per_cell_);
    return {hit, pattern_[cell].weight / (p + 1.0), cell_sigma_ / std::sqrt(p)};
}

void PulseSimulator::edge_cells(std::span<const std::int64_t> target,
                                std::vector<std::uint32_t>& out) const {
    out.clear();
    if (probes_per_cell_ == 0 || target.size() != neighbours_.size()) {
        return;
    }
    if (std::all_of(target.begin(), target.end(), [&](auto t) { return t == target[0]; })) {
        return;
    }
    for (std::size_t j = 0; j < target.size(); ++j) {
        for (const std::uint32_t m : neighbours_[j]) {
            if (target[m] != target[j]) {
                out.push_back(static_cast<std::uint32_t>(j));
                break;
            }
        }
    }
}

void PulseSimulator::probe_rays(const Vec3d& origin, const Vec3d& axis, std::size_t cell,
                                std::span<Vec3d> origins, std::span<Vec3d> dirs) const {
    assert(origins.size() == probes_per_cell_ && dirs.size() == probes_per_cell_);
    const std::span<const Vec3d> frame{probe_frame_.data() + cell * probes_per_cell_,
                                       probes_per_cell_};
    beamtrace::sub_ray_directions(axis, frame, dirs);
    if (config_.beam.exit_diameter_m > 0) {
        beamtrace::sub_ray_origins(
            origin, axis, {probe_origins_.data() + cell * probes_per_cell_, probes_per_cell_},
            origins);
    } else {
        std::fill(origins.begin(), origins.end(), origin);
    }
}

void PulseSimulator::simulate_samples(std::uint64_t seed, std::uint64_t pulse_index,
                                      std::span<const BeamSample> samples,
                                      PulseResponse& out) const {
    out.dropped = false;
    out.returns.clear();
    out.echoes.clear();
    out.contributions.clear();
    out.sub_ray_power_w.clear();
    // The whole waveform, first bin included: `out` is reused from pulse to pulse (a survey
    // block's PulseResponse), and a miss or a dropped pulse returns before build_waveform sets
    // it, so it would keep the bin of whichever pulse the response last held.
    out.waveform.samples_w.clear();
    out.waveform.first_bin = 0;
    if (pulse_dropped(config_.noise, seed, pulse_index)) {
        out.dropped = true;
        return;
    }
    sample_contributions(seed, pulse_index, samples, out);
    // The fog's binned slabs (none without a medium: out.medium may hold another's).
    const BinnedEcho& binned = medium_ ? out.medium.fog.binned : kNoBinnedEcho;
    if (out.contributions.empty() && binned.empty()) {
        return;
    }
    const WaveformConfig& wf = config_.waveform;
    if (medium_ && !config_.keep_waveform) {  // the weather's pulses, group by group
        detect_echoes_in_groups(wf, out.contributions, binned,
                                config_.radiometry.detection_threshold_w, out.echoes,
                                medium_->group_reach_sigmas());
    } else {
        build_waveform(wf, out.contributions, binned, out.waveform);
        detect_echoes(wf, out.waveform, config_.radiometry.detection_threshold_w, out.echoes);
    }
    if (!config_.keep_waveform) {
        out.waveform.samples_w.clear();
    }
    if (out.echoes.empty()) {
        return;
    }

    const auto [begin, end] = reported_echoes(out.echoes, config_.return_mode,
                                              static_cast<std::size_t>(config_.max_returns));
    const auto count = static_cast<std::uint8_t>(end - begin);
    for (std::size_t e = begin; e < end; ++e) {
        const Echo& echo = out.echoes[e];
        PulseReturn r;
        // Noise is keyed by the echo's index among all echoes: a mode never changes a range.
        r.range_m = echo.range_m + range_noise_m(config_.noise, seed, pulse_index,
                                                 static_cast<std::uint32_t>(e), echo.range_m);
        r.amplitude_w = echo.amplitude_w;
        r.power_w = echo.power_w;
        r.echo_width_ns = echo.width_ns;
        r.intensity = las_intensity(config_.radiometry, echo.power_w);
        r.return_number = static_cast<std::uint8_t>(e - begin + 1);
        r.number_of_returns = count;
        const auto [sample, share] =
            dominant_sample(samples, out.sub_ray_power_w, out.contributions, echo.range_m);
        r.sub_ray = sample;
        if (medium_) {
            r.weather = medium_dominates(out, share, echo.range_m);
        }
        out.returns.push_back(r);
    }
}

void PulseSimulator::sample_contributions(std::uint64_t seed, std::uint64_t pulse_index,
                                          std::span<const BeamSample> samples,
                                          PulseResponse& out) const {
    const std::size_t n = samples.size();
    std::vector<double>& powers = out.sub_ray_power_w;
    powers.resize(n);
    sub_ray_powers(samples, powers);
    if (!medium_) {  // no shadows to take off: the widths in a loop of their own, then the echoes
        std::vector<double>& sigmas = out.sigma_ns;
        echo_sigmas(samples, sigmas);
        // Every sample written at the next place, which moves on for the lit ones (no branch).
        std::vector<EchoContribution>& c = out.contributions;
        std::size_t m = c.size();
        c.resize(m + n);
        for (std::size_t j = 0; j < n; ++j) {
            c[m] = {samples[j].hit.range_m, powers[j], sigmas[j]};
            m += powers[j] > 0 ? 1 : 0;
        }
        c.resize(m);
        return;
    }
    add_medium(seed, pulse_index, samples, out);
    for (std::size_t j = 0; j < n; ++j) {
        const BeamSample& s = samples[j];
        if (powers[j] > 0) {
            out.contributions.push_back(
                {s.hit.range_m, powers[j], echo_sigma_ns(s.hit, s.cell_sigma)});
        }
    }
    // The medium's after the samples' (dominant_sample counts on their order).
    out.contributions.insert(out.contributions.end(), out.medium.contributions.begin(),
                             out.medium.contributions.end());
}

void PulseSimulator::add_medium(std::uint64_t seed, std::uint64_t pulse_index,
                                std::span<const BeamSample> samples, PulseResponse& out) const {
    const double far_m = medium_->max_range_m();
    out.shares.clear();
    for (const BeamSample& s : samples) {
        const double r = s.hit.range_m;
        out.shares.push_back({s.weight, std::isfinite(r) && r > 0 ? std::min(r, far_m) : far_m});
    }
    medium_->echoes(seed, pulse_index, out.shares, out.medium);
    for (const Particle& p : out.medium.particles) {
        for (std::size_t j = 0; j < samples.size(); ++j) {
            if (samples[j].hit.range_m > p.range_m) {
                out.sub_ray_power_w[j] *= 1.0 - p.blocked_fraction;
            }
        }
    }
}

WeatherEffect PulseSimulator::medium_dominates(const PulseResponse& out, double sample_share,
                                               double range_m) const {
    const double sigma_m = config_.waveform.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0))) /
                           round_trip_ns_per_m();
    const MediumEchoes& m = out.medium;
    // The medium's contributions add up at the echo's peak (a fog's slabs are one echo).
    double fog = medium_->binned_fog_share(m, range_m, sigma_m), particles = 0.0;
    for (std::size_t i = 0; i < m.contributions.size(); ++i) {
        const double d = (m.contributions[i].range_m - range_m) / sigma_m;
        const double share = m.contributions[i].power_w / sigma_m * std::exp(-0.5 * d * d);
        (m.effects[i] == WeatherEffect::fog ? fog : particles) += share;
    }
    if (std::max(fog, particles) <= sample_share) {
        return WeatherEffect::none;
    }
    if (fog >= particles) {
        return WeatherEffect::fog;
    }
    return particle_effect(config_.weather->precipitation->kind);
}

PulseResponse simulate_pulse(const PhysicsConfig& config, std::uint64_t seed,
                             std::uint64_t pulse_index, std::span<const SubRayHit> hits) {
    PulseResponse out;
    PulseSimulator(config).simulate(seed, pulse_index, hits, out);
    return out;
}

}  // namespace beamtrace
