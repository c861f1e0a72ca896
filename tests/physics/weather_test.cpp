// Fog (soft target) and precipitation (particles) against closed forms and independent
// numerical integrals.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "beamtrace/physics/atmosphere.hpp"
#include "beamtrace/physics/fog.hpp"
#include "beamtrace/physics/precipitation.hpp"
#include "beamtrace/physics/waveform.hpp"

namespace beamtrace {
namespace {

/// Adaptive Simpson integration of f over [a, b] to relative tolerance `tol`.
double integrate(const std::function<double(double)>& f, double a, double b, double tol = 1e-9) {
    const std::function<double(double, double, double, double, double, double, int)> step =
        [&](double lo, double hi, double flo, double fmid, double fhi, double whole, int depth) {
            const double mid = (lo + hi) / 2.0;
            const double fl = f((lo + mid) / 2.0);
            const double fr = f((mid + hi) / 2.0);
            const double left = (mid - lo) / 6.0 * (flo + 4.0 * fl + fmid);
            const double right = (hi - mid) / 6.0 * (fmid + 4.0 * fr + fhi);
            if (depth > 40 ||
                std::abs(left + right - whole) <= 15.0 * tol * std::abs(left + right)) {
                return left + right + (left + right - whole) / 15.0;
            }
            return step(lo, mid, flo, fl, fmid, left, depth + 1) +
                   step(mid, hi, fmid, fr, fhi, right, depth + 1);
        };
    const double fa = f(a), fb = f(b), fm = f((a + b) / 2.0);
    return step(a, b, fa, fm, fb, (b - a) / 6.0 * (fa + 4.0 * fm + fb), 0);
}

/// Piecewise integration over many pieces (the integrands have sharp pulses).
double integrate_pieces(const std::function<double(double)>& f, double a, double b, int pieces) {
    double sum = 0.0;
    for (int i = 0; i < pieces; ++i) {
        const double lo = a + (b - a) * i / pieces, hi = a + (b - a) * (i + 1) / pieces;
        sum += integrate(f, lo, hi, 1e-10);
    }
    return sum;
}

TEST(WeatherFog, ExtinctionLeavesFivePercentOverTheMor) {
    for (const double mor : {25.0, 50.0, 200.0, 1000.0}) {
        const FogConfig fog{mor, {}, {}};
        EXPECT_TRUE(fog.validate().empty());
        const double alpha = fog_extinction_per_m(fog);
        EXPECT_NEAR(std::exp(-alpha * mor), 0.05, 1e-12) << mor;
        // A hard target at R sees the two-way transmission exp(-2 alpha R).
        EXPECT_NEAR(two_way_transmission(alpha, mor / 2.0), 0.05, 1e-12) << mor;
        EXPECT_NEAR(fog_backscatter_per_m_sr(fog) * mor, 0.046, 1e-15);
    }
    const FogConfig given{50.0, 0.01, 2e-4};
    EXPECT_EQ(fog_extinction_per_m(given), 0.01);
    EXPECT_EQ(fog_backscatter_per_m_sr(given), 2e-4);
    EXPECT_FALSE((FogConfig{0.0, {}, {}}.validate().empty()));
    EXPECT_FALSE((FogConfig{50.0, -1.0, {}}.validate().empty()));
    EXPECT_FALSE((OverlapConfig{0.0, 1.0}.validate().empty()));  // 1/r at r = 0
    EXPECT_FALSE((OverlapConfig{2.0, 1.0}.validate().empty()));
}

TEST(WeatherFog, OverlapRampsLinearly) {
    const OverlapConfig o{0.5, 2.0};
    EXPECT_EQ(overlap_fraction(o, 0.2), 0.0);
    EXPECT_EQ(overlap_fraction(o, 0.5), 0.0);
    EXPECT_NEAR(overlap_fraction(o, 1.25), 0.5, 1e-15);
    EXPECT_EQ(overlap_fraction(o, 2.0), 1.0);
    EXPECT_EQ(overlap_fraction(o, 70.0), 1.0);
}

/// The soft-target waveform of a uniform fog, sampled by the digitiser, against the integral
/// P_t eta A_r beta integral xi(r) exp(-2 alpha r) / r^2 g(t - 2 r / c) dr computed here.
TEST(WeatherFog, BackscatterWaveformEqualsTheSoftTargetIntegral) {
    const FogConfig fog{50.0, {}, {}};
    const SoftTarget medium{fog_backscatter_per_m_sr(fog), fog_extinction_per_m(fog), {0.5, 2.0}};
    const double p_t = 1000.0, gain = 0.8 * std::numbers::pi * 0.025 * 0.025, end_m = 40.0;
    WaveformConfig wf;  // 4 ns FWHM, 0.5 ns bins
    std::vector<EchoContribution> slabs;
    // Slabs of half the pulse's c sigma_p / 2 (0.127 m at 4 ns), a fifth of it on the overlap
    // ramp, as WeatherMedium uses.
    add_soft_target_echo(medium, p_t, gain, end_m, {0.127, 0.0254, 0.0}, slabs);
    ASSERT_GT(slabs.size(), 250u);
    Waveform w;
    build_waveform(wf, slabs, w);
    ASSERT_FALSE(w.samples_w.empty());

    const double sigma_ns = wf.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    const auto exact = [&](double t_ns) {
        const auto integrand = [&](double r) {
            const double dt = t_ns - r * round_trip_ns_per_m();
            return overlap_fraction(medium.overlap, r) *
                   std::exp(-2.0 * medium.extinction_per_m * r) / (r * r) *
                   std::exp(-dt * dt / (2.0 * sigma_ns * sigma_ns));
        };
        // The pulse is 5 sigma wide at most: integrate where it is.
        const double centre = t_ns / round_trip_ns_per_m();
        const double half = 6.0 * sigma_ns / round_trip_ns_per_m();
        const double lo = std::max(medium.overlap.start_m, centre - half);
        const double hi = std::min(end_m, centre + half);
        if (!(hi > lo)) {
            return 0.0;
        }
        return p_t * gain * medium.backscatter_per_m_sr * integrate_pieces(integrand, lo, hi, 8);
    };
    double peak = 0.0;
    for (const double s : w.samples_w) {
        peak = std::max(peak, s);
    }
    std::size_t compared = 0;
    for (std::size_t k = 0; k < w.samples_w.size(); ++k) {
        const double want = exact(w.time_ns(k));
        if (want < 0.01 * peak) {
            continue;
        }
        EXPECT_NEAR(w.samples_w[k], want, 0.02 * want) << "t " << w.time_ns(k) << " ns";
        ++compared;
    }
    EXPECT_GT(compared, 100u);
}

TEST(WeatherFog, CutoffEndsTheSumWhereTheEchoIsNegligible) {
    const SoftTarget medium{0.046 / 50.0, std::log(20.0) / 50.0, {0.5, 2.0}};
    std::vector<EchoContribution> all, cut;
    add_soft_target_echo(medium, 1000.0, 1e-3, 300.0, {0.05, 0.0}, all);
    add_soft_target_echo(medium, 1000.0, 1e-3, 300.0, {0.05, 0.0, 1e-12}, cut);
    ASSERT_LT(cut.size(), all.size());
    for (std::size_t i = 0; i < cut.size(); ++i) {
        EXPECT_EQ(cut[i].range_m, all[i].range_m);
        EXPECT_EQ(cut[i].power_w, all[i].power_w);
    }
    for (std::size_t i = cut.size(); i < all.size(); ++i) {
        EXPECT_LT(all[i].power_w, 1e-12);
    }
    // The path ends at the hard target: nothing behind it.
    std::vector<EchoContribution> short_path;
    add_soft_target_echo(medium, 1000.0, 1e-3, 10.02, {0.05, 0.0}, short_path);
    ASSERT_FALSE(short_path.empty());
    EXPECT_LT(short_path.back().range_m, 10.02);
    EXPECT_GT(short_path.back().range_m, 9.99);
}

TEST(WeatherFog, HardTargetsShadowTheFogBehindThem) {
    const SoftTarget medium{0.046 / 30.0, std::log(20.0) / 30.0, {0.5, 2.0}};
    // Half the beam stops at 5 m, the other half at 20 m: the fog's echo is half the echo of
    // a path to 5 m plus half the echo of a path to 20 m.
    std::vector<BeamShare> shares{{0.5, 20.0}, {0.5, 5.0}};
    std::vector<EchoContribution> split, near, far;
    add_soft_target_echo(medium, 1000.0, 1e-3, shares, {0.05, 0.0}, split);
    add_soft_target_echo(medium, 500.0, 1e-3, 5.0, {0.05, 0.0}, near);
    add_soft_target_echo(medium, 500.0, 1e-3, 20.0, {0.05, 0.0}, far);
    near.insert(near.end(), far.begin(), far.end());
    WaveformConfig wf;
    Waveform a, b;
    build_waveform(wf, split, a);
    build_waveform(wf, near, b);
    ASSERT_EQ(a.first_bin, b.first_bin);
    ASSERT_EQ(a.samples_w.size(), b.samples_w.size());
    for (std::size_t k = 0; k < a.samples_w.size(); ++k) {
        EXPECT_NEAR(a.samples_w[k], b.samples_w[k], 1e-6 * b.samples_w[k] + 1e-20) << k;
    }
    // No slab lies behind the last target.
    for (const EchoContribution& c : split) {
        EXPECT_LT(c.range_m, 20.0);
    }
    std::vector<BeamShare> open{{1.0, std::numeric_limits<double>::infinity()}};
    EXPECT_THROW(add_soft_target_echo(medium, 1.0, 1.0, open, {0.05, 0.0}, split),
                 std::invalid_argument);
}

// The survey's precomputed fog (SoftTargetProfile: slabs summed per bin once) against the slab
// walk of add_soft_target_echo, pulse by pulse: beams whose shares end before, inside and
// beyond the fog's reach, cut on the overlap ramp, misses, a beam heavier than the table's.
TEST(WeatherFog, ProfileGivesTheSlabWalksWaveform) {
    const SoftTarget medium{0.046 / 40.0, std::log(20.0) / 40.0, {0.5, 2.0}};
    const WaveformConfig wf;
    const SoftTargetSampling sampling{0.127, 0.0254, 1e-3 * 2e-8};
    const double p_t = 30.0, gain = 1.5e-3, far_m = 200.0;
    const SoftTargetProfile profile(medium, p_t, gain, sampling, wf, far_m);
    ASSERT_FALSE(profile.empty());
    const double sigma_m =
        wf.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0))) / round_trip_ns_per_m();
    const std::vector<std::vector<BeamShare>> beams{
        {{1.0, far_m}},
        {{0.5, far_m}, {0.5, 7.3}},
        {{0.25, 12.0}, {0.25, 12.0}, {0.25, 12.05}, {0.25, far_m}},
        {{0.7, 1.2}, {0.3, 30.0}},   // one share ends on the ramp
        {{1.0, 0.3}},                // inside the blind zone: no fog
        {{0.6, 2.0}, {0.6, far_m}},  // heavier than one beam
        {{1.0, 45.0}}};
    for (std::size_t i = 0; i < beams.size(); ++i) {
        std::vector<BeamShare> a = beams[i], b = beams[i];
        std::vector<EchoContribution> walk, rest;
        add_soft_target_echo(medium, p_t, gain, a, sampling, walk);
        SoftTargetEcho binned;
        profile.echo(b, binned, rest);
        Waveform want, got;
        build_waveform(wf, walk, want);
        build_waveform(wf, rest, binned.binned, got);
        ASSERT_EQ(got.first_bin, want.first_bin) << i;
        ASSERT_EQ(got.samples_w.size(), want.samples_w.size()) << i;
        double peak = 0.0;
        for (const double v : want.samples_w) {
            peak = std::max(peak, v);
        }
        for (std::size_t k = 0; k < want.samples_w.size(); ++k) {
            EXPECT_NEAR(got.samples_w[k], want.samples_w[k], 1e-12 * peak) << i << " " << k;
        }
        EXPECT_EQ(binned.slabs + rest.size(), walk.size()) << i;
        // What the binned slabs add at an echo's peak, against the sum over the walk's slabs.
        for (const double r : {1.0, 1.35, 2.4, 7.0, 11.9, 20.0}) {
            double brute = 0.0;
            for (std::size_t s = 0; s < binned.slabs; ++s) {
                const double d = (walk[s].range_m - r) / sigma_m;
                brute += walk[s].power_w / sigma_m * std::exp(-0.5 * d * d);
            }
            EXPECT_NEAR(profile.share_at(binned, r, sigma_m), brute, 1e-12 * brute + 1e-30)
                << i << " " << r;
        }
    }
}

TEST(WeatherPrecipitation, DistributionsFollowTheirPublishedForms) {
    const auto rain = drop_size_distribution(PrecipitationKind::rain, 10.0);
    EXPECT_EQ(rain.n0_per_m3_mm, 8000.0);
    EXPECT_NEAR(rain.slope_per_mm, 4.1 * std::pow(10.0, -0.21), 1e-12);
    const auto snow = drop_size_distribution(PrecipitationKind::snow, 2.0);
    EXPECT_NEAR(snow.n0_per_m3_mm, 3800.0 * std::pow(2.0, -0.87), 1e-9);
    EXPECT_NEAR(snow.slope_per_mm, 2.55 * std::pow(2.0, -0.48), 1e-12);
    // Density and extinction against the integrals of N(D) (D in mm, up to 40 mean sizes).
    for (const auto& dsd : {rain, snow}) {
        const auto n = [&](double d) { return dsd.n0_per_m3_mm * std::exp(-dsd.slope_per_mm * d); };
        const double top = 40.0 / dsd.slope_per_mm;
        EXPECT_NEAR(number_density_per_m3(dsd), integrate(n, 0.0, top),
                    1e-6 * integrate(n, 0, top));
        const double alpha = integrate(
            [&](double d) { return 2.0 * std::numbers::pi * d * d / 4.0 * n(d) * 1e-6; }, 0.0, top);
        EXPECT_NEAR(extinction_per_m(dsd), alpha, 1e-6 * alpha);
    }
    // Marshall-Palmer at 10 mm/h: about 1.6 per km, as the empirical 0.365 R^0.63 per km gives.
    EXPECT_NEAR(extinction_per_m(rain) * 1000.0, 0.365 * std::pow(10.0, 0.63), 0.1);
    EXPECT_EQ(parse_precipitation_kind("snow"), PrecipitationKind::snow);
    EXPECT_ANY_THROW((void)parse_precipitation_kind("hail"));
}

TEST(WeatherPrecipitation, PoissonCountsHaveTheirMeanAndVariance) {
    for (const double mean : {0.3, 4.0, 450.0}) {
        const int n = 20000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            CounterRng rng(7, static_cast<std::uint64_t>(i), 0, RngStream::weather_particles);
            const auto k = static_cast<double>(poisson_count(rng, mean));
            sum += k;
            sum2 += k * k;
        }
        const double m = sum / n, var = sum2 / n - m * m;
        EXPECT_NEAR(m, mean, 5.0 * std::sqrt(mean / n)) << mean;
        EXPECT_NEAR(var, mean, 0.05 * mean) << mean;
    }
}

/// A heavy-rain beam of a car sensor: 3 mrad, 1 cm exit radius.
ParticleBeam rain_beam(double extinction) {
    ParticleBeam b;
    b.exit_radius_m = 0.01;
    b.half_angle_rad = 1.5e-3;
    b.emitted_power_w = 100.0;
    b.receiver_gain_m2 = 0.8 * std::numbers::pi * 0.0125 * 0.0125;
    b.extinction_per_m = extinction;
    b.floor_w = 1e-7;
    b.start_m = 0.5;
    b.overlap = {0.5, 2.0};
    b.max_range_m = 150.0;
    return b;
}

/// The number of particles of echo >= floor per pulse over 10^5 pulses against the expected
/// count: the integral over the cell's volume of the density of particles larger than the least
/// detectable diameter, derived here from the echo's formula.
TEST(WeatherPrecipitation, ParticleEchoesPerPulseMatchTheExpectedCount) {
    const auto dsd = drop_size_distribution(PrecipitationKind::rain, 25.0);
    const ParticleBeam beam = rain_beam(extinction_per_m(dsd));
    const ParticleCell cell{0.25, 0.2};
    const double albedo = 0.02, end_m = 60.0;
    const ParticleSampler sampler(dsd, albedo, beam, cell);

    const auto area = [&](double r) {
        const double w = beam.exit_radius_m + r * std::tan(beam.half_angle_rad);
        return cell.area_fraction * std::numbers::pi * w * w;
    };
    const auto least_mm = [&](double r) {
        // P = (2/3)(a/pi) (pi D^2 / 4) / A w P_t g exp(-2 alpha r) / r^2 = floor, D^2 below A.
        const double k = 2.0 / 3.0 * albedo / std::numbers::pi * cell.energy_fraction *
                         beam.emitted_power_w * beam.receiver_gain_m2 *
                         std::min(1.0, (r - 0.5) / 1.5) *
                         std::exp(-2.0 * beam.extinction_per_m * r) / (r * r);
        if (k < beam.floor_w) {
            return std::numeric_limits<double>::infinity();
        }
        return std::sqrt(beam.floor_w / k * 4.0 * area(r) / std::numbers::pi) * 1000.0;
    };
    const double expected = integrate_pieces(
        [&](double r) {
            const double d = least_mm(r);
            return std::isfinite(d) ? area(r) * dsd.n0_per_m3_mm / dsd.slope_per_mm *
                                          std::exp(-dsd.slope_per_mm * d)
                                    : 0.0;
        },
        beam.start_m, end_m, 64);
    ASSERT_GT(expected, 0.05);
    EXPECT_NEAR(sampler.expected_count(end_m), expected, 1e-3 * expected);

    const int pulses = 100000;
    std::vector<Particle> particles;
    double range_sum = 0.0;
    for (int i = 0; i < pulses; ++i) {
        CounterRng rng(11, static_cast<std::uint64_t>(i), 3, RngStream::weather_particles);
        const std::size_t before = particles.size();
        sampler.sample(rng, end_m, particles);
        for (std::size_t j = before; j < particles.size(); ++j) {
            const Particle& p = particles[j];
            EXPECT_GE(p.range_m, beam.start_m);
            EXPECT_LE(p.range_m, end_m);
            EXPECT_GE(p.echo_power_w, beam.floor_w * (1.0 - 1e-9));
            EXPECT_NEAR(p.echo_power_w, sampler.echo_power_w(p.diameter_m, p.range_m), 1e-18);
            range_sum += p.range_m;
        }
    }
    const double per_pulse = static_cast<double>(particles.size()) / pulses;
    EXPECT_NEAR(per_pulse, expected, 0.05 * expected);
    RecordProperty("particles_per_pulse", std::to_string(per_pulse));
    // The ranges follow the density: their mean is the density's mean range.
    const double mean_range =
        integrate_pieces(
            [&](double r) {
                const double d = least_mm(r);
                return std::isfinite(d) ? r * area(r) * std::exp(-dsd.slope_per_mm * d) : 0.0;
            },
            beam.start_m, end_m, 64) /
        integrate_pieces(
            [&](double r) {
                const double d = least_mm(r);
                return std::isfinite(d) ? area(r) * std::exp(-dsd.slope_per_mm * d) : 0.0;
            },
            beam.start_m, end_m, 64);
    EXPECT_NEAR(range_sum / static_cast<double>(particles.size()), mean_range, 0.02 * mean_range);
}

TEST(WeatherPrecipitation, SameKeySameParticlesAndNoneBehindTheTarget) {
    const auto dsd = drop_size_distribution(PrecipitationKind::snow, 5.0);
    const ParticleSampler sampler(dsd, default_particle_albedo(PrecipitationKind::snow),
                                  rain_beam(extinction_per_m(dsd)), {1.0, 1.0});
    std::vector<Particle> a, b, near;
    for (std::uint64_t i = 0; i < 2000; ++i) {
        CounterRng r1(5, i, 0, RngStream::weather_particles),
            r2(5, i, 0, RngStream::weather_particles);
        sampler.sample(r1, 100.0, a);
        sampler.sample(r2, 100.0, b);
        CounterRng r3(5, i, 0, RngStream::weather_particles);
        sampler.sample(r3, 3.0, near);
    }
    ASSERT_FALSE(a.empty());
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].range_m, b[i].range_m);
        EXPECT_EQ(a[i].diameter_m, b[i].diameter_m);
    }
    for (const Particle& p : near) {
        EXPECT_LE(p.range_m, 3.0);
    }
    EXPECT_LT(near.size(), a.size());
}

}  // namespace
}  // namespace beamtrace
