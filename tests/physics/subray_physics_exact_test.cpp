// The sub-ray physics' shortcuts (issue 21) give the results of the plain computations bit for
// bit: the waveform's Gaussians sampled several at a time, the dominant sample's search, the
// footprint radius without hypot.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "beamtrace/physics/atmosphere.hpp"
#include "beamtrace/physics/beam_divergence.hpp"
#include "beamtrace/physics/material.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/physics/range_equation.hpp"
#include "beamtrace/physics/waveform.hpp"
#include "physics/detail/fast_exp.hpp"

namespace beamtrace {
namespace {

/// The waveform as build_waveform made it before issue 21: one Gaussian after the other, each
/// along its bins by the recurrence g *= ratio, ratio *= step (three exps, ours: fast_exp).
Waveform one_gaussian_at_a_time(const WaveformConfig& config,
                                const std::vector<EchoContribution>& contributions) {
    Waveform out;
    out.bin_ns = config.bin_ns;
    const double sigma_p = config.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    const auto sigma_of = [&](const EchoContribution& c) {
        return c.sigma_ns > 0 ? c.sigma_ns : sigma_p;
    };
    double t_lo = contributions[0].range_m, t_hi = t_lo, sigma_max = 0.0;
    for (const auto& c : contributions) {
        t_lo = std::min(t_lo, c.range_m);
        t_hi = std::max(t_hi, c.range_m);
        sigma_max = std::max(sigma_max, sigma_of(c));
    }
    t_lo = t_lo * round_trip_ns_per_m() - 5.0 * sigma_max;
    t_hi = t_hi * round_trip_ns_per_m() + 5.0 * sigma_max;
    const auto first = static_cast<std::int64_t>(std::floor(t_lo / config.bin_ns));
    const auto last = static_cast<std::int64_t>(std::ceil(t_hi / config.bin_ns));
    out.first_bin = first;
    out.samples_w.assign(static_cast<std::size_t>(last - first + 1), 0.0);
    const double h = config.bin_ns;
    for (const auto& c : contributions) {
        const double t = c.range_m * round_trip_ns_per_m();
        const double sigma = sigma_of(c);
        const auto b0 = std::max(
            first, static_cast<std::int64_t>(std::floor((t - 5.0 * sigma) / config.bin_ns)));
        const auto b1 =
            std::min(last, static_cast<std::int64_t>(std::ceil((t + 5.0 * sigma) / config.bin_ns)));
        const double amplitude = c.sigma_ns > 0 ? c.power_w * (sigma_p / sigma) : c.power_w;
        const double inv_two_var = 1.0 / (2.0 * sigma * sigma);
        const double dt0 = static_cast<double>(b0) * h - t;
        double g = amplitude * detail::fast_exp(-dt0 * dt0 * inv_two_var);
        double ratio = detail::fast_exp(-(2.0 * dt0 * h + h * h) * inv_two_var);
        const double step = detail::fast_exp(-2.0 * h * h * inv_two_var);
        for (std::int64_t b = b0; b <= b1; ++b) {
            out.samples_w[static_cast<std::size_t>(b - first)] += g;
            g *= ratio;
            ratio *= step;
        }
    }
    return out;
}

/// Whether two waveforms start at the same bin and hold the same samples, bit for bit (the
/// first differing bin named).
::testing::AssertionResult same_bits(const Waveform& w, const Waveform& expected) {
    if (w.first_bin != expected.first_bin || w.samples_w.size() != expected.samples_w.size()) {
        return ::testing::AssertionFailure()
               << "bins " << w.first_bin << " + " << w.samples_w.size() << ", expected "
               << expected.first_bin << " + " << expected.samples_w.size();
    }
    for (std::size_t k = 0; k < w.samples_w.size(); ++k) {
        if (std::bit_cast<std::uint64_t>(w.samples_w[k]) !=
            std::bit_cast<std::uint64_t>(expected.samples_w[k])) {
            return ::testing::AssertionFailure() << "bin " << k << ": " << w.samples_w[k]
                                                 << ", expected " << expected.samples_w[k];
        }
    }
    return ::testing::AssertionSuccess();
}

/// n echo contributions of random power (1e-7 W times [0.01, 1.01)): three in ten of the pulse's
/// width (sigma 0), the others of width(u), each at range(u) metres; u() draws from [0, 1).
template <class Width, class Range>
std::vector<EchoContribution> random_echoes(std::size_t n, std::mt19937_64& rng, Width width,
                                            Range range) {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    auto u = [&] { return uniform(rng); };
    std::vector<EchoContribution> c;
    for (std::size_t i = 0; i < n; ++i) {
        const double sigma = u() < 0.3 ? 0.0 : width(u);
        const double range_m = range(u);
        c.push_back({range_m, 1e-7 * (0.01 + u()), sigma});
    }
    return c;
}

TEST(PhysicsSubRayExact, WaveformIsBitIdenticalToOneGaussianAtATime) {
    std::mt19937_64 rng(21);
    WaveformConfig config;
    // 1 to 21 contributions: groups of four and eight and every remainder; widths from the pulse's
    // to 20 times it, so the runs of one group differ in length (and the longest's tail runs
    // alone).
    for (int trial = 0; trial < 400; ++trial) {
        const auto c = random_echoes(
            1 + static_cast<std::size_t>(trial % 21), rng,
            [](auto& u) { return 1.7 * (1.0 + 19.0 * u() * u()); },
            [](auto& u) { return 1500.0 + 3.0 * u(); });
        Waveform w;
        build_waveform(config, c, w);
        ASSERT_TRUE(same_bits(w, one_gaussian_at_a_time(config, c))) << "trial " << trial;
        // And the samples are the Gaussians' sum (closed form) to rounding.
        const double sigma_p = config.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
        for (std::size_t k = 0; k < w.samples_w.size(); k += 7) {
            double sum = 0.0, reach = 0.0;
            for (const auto& e : c) {
                const double s = e.sigma_ns > 0 ? e.sigma_ns : sigma_p;
                const double t = e.range_m * round_trip_ns_per_m();
                const double d = (w.time_ns(k) - t) / s;
                // The bins the waveform samples: those reaching 5 sigma each side.
                const auto b = static_cast<double>(w.first_bin + static_cast<std::int64_t>(k));
                if (b >= std::floor((t - 5.0 * s) / config.bin_ns) &&
                    b <= std::ceil((t + 5.0 * s) / config.bin_ns)) {
                    sum += e.power_w * (sigma_p / s) * std::exp(-0.5 * d * d);
                }
                reach += e.power_w;
            }
            ASSERT_NEAR(w.samples_w[k], sum, 1e-9 * reach) << "trial " << trial << " bin " << k;
        }
    }
}

/// The index of the sample whose echo adds most at `range_m` (the first of equal ones), from
/// every sample's share (no shortcut).
std::uint32_t brute_force_dominant(const PulseResponse& r, double range_m) {
    double best = -1.0;
    std::uint32_t best_j = 0;
    for (std::size_t j = 0, c = 0; j < r.sub_ray_power_w.size(); ++j) {
        const double p = r.sub_ray_power_w[j];
        if (p > 0) {
            const double sigma_m = r.contributions[c++].sigma_ns / round_trip_ns_per_m();
            const double d = (r.samples[j].hit.range_m - range_m) / sigma_m;
            const double share = p / sigma_m * std::exp(-0.5 * d * d);
            if (share > best) {
                best = share;
                best_j = static_cast<std::uint32_t>(j);
            }
        }
    }
    return best_j;
}

TEST(PhysicsSubRayExact, DominantSampleIsTheBruteForceOne) {
    PhysicsConfig config;
    config.beam.divergence_rad = 0.003;
    config.beam.rings = 2;
    const PulseSimulator sim(config);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::size_t outer = 0;  // echoes whose dominant sample is on the outer ring
    PulseResponse r;
    for (std::uint64_t pulse = 0; pulse < 2000; ++pulse) {
        // Two or three surfaces a few metres apart, the outer ring's on its own at times: the
        // faint outer cells then dominate an echo that the centre's bound does not reach.
        const double near_m = 100.0 + 50.0 * u(rng), far_m = near_m + 2.0 + 6.0 * u(rng);
        const bool split = u(rng) < 0.5;
        std::vector<SubRayHit> hits(sim.sub_ray_count());
        for (std::size_t j = 0; j < hits.size(); ++j) {
            const bool outer_ring = j >= 7;
            hits[j].range_m = (outer_ring && split ? far_m : near_m) + 0.3 * u(rng);
            hits[j].cos_incidence = 0.2 + 0.8 * u(rng);
            hits[j].albedo = 0.05 + 0.9 * u(rng);
            if (u(rng) < 0.1) {
                hits[j] = SubRayHit{};  // a miss
            }
        }
        sim.simulate(1, pulse, hits, r);
        for (const PulseReturn& ret : r.returns) {
            const std::size_t e = static_cast<std::size_t>(&ret - r.returns.data());
            const double range_m = r.echoes[e].range_m;  // mode all: returns are the echoes
            ASSERT_EQ(ret.sub_ray, brute_force_dominant(r, range_m)) << "pulse " << pulse;
            outer += ret.sub_ray >= 7 ? 1 : 0;
        }
    }
    EXPECT_GT(outer, 100u);  // the case the shortcut skips most in is exercised
}

TEST(PhysicsSubRayExact, WaveformNearZeroAndFarIsBitIdenticalToOneGaussianAtATime) {
    // Runs whose bins start below 0, at 0 and far out (their bins and exponents four at a
    // time), fours with empty or clipped runs: bit for bit the one-at-a-time waveform.
    std::mt19937_64 rng(5);
    WaveformConfig config;
    for (int trial = 0; trial < 300; ++trial) {
        const double base_m = trial % 3 == 0 ? 0.0 : (trial % 3 == 1 ? 0.37 : 2.5e5);
        const auto c = random_echoes(
            1 + static_cast<std::size_t>(trial % 19), rng,
            [](auto& u) { return 1.7 * (1.0 + 9.0 * u()); },
            [base_m](auto& u) { return u() < 0.2 ? base_m : base_m + 2.0 * u(); });
        Waveform w;
        build_waveform(config, c, w);
        ASSERT_TRUE(same_bits(w, one_gaussian_at_a_time(config, c))) << "trial " << trial;
    }
}

/// Whether the pulse's powers (simulate_samples, into r) are sub_ray_power_w's of each sample,
/// bit for bit (the first differing sample named).
::testing::AssertionResult powers_are_each_samples(const PulseSimulator& sim, std::uint64_t pulse,
                                                   const std::vector<BeamSample>& samples,
                                                   PulseResponse& r) {
    sim.simulate_samples(1, pulse, samples, r);
    if (r.sub_ray_power_w.size() != samples.size()) {
        return ::testing::AssertionFailure() << r.sub_ray_power_w.size() << " powers";
    }
    for (std::size_t j = 0; j < samples.size(); ++j) {
        const double p = sim.sub_ray_power_w(samples[j].hit, samples[j].weight);
        if (std::bit_cast<std::uint64_t>(r.sub_ray_power_w[j]) != std::bit_cast<std::uint64_t>(p)) {
            return ::testing::AssertionFailure()
                   << "sample " << j << ": " << r.sub_ray_power_w[j] << ", expected " << p;
        }
    }
    return ::testing::AssertionSuccess();
}

TEST(PhysicsSubRayExact, SubRayPowersInLanesAreEachHitsPowerBitForBit) {
    // Up to 61 samples (the lanes' chunks of 32 and their tails), misses and bad ranges among
    // them, through an atmosphere: the pulse's powers are sub_ray_power_w's one by one, and
    // within 2 ulps of the range equation with std::exp's transmission.
    PhysicsConfig config;
    config.atmosphere.extinction_per_m_override = 2e-4;
    const PulseSimulator sim(config);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    PulseResponse r;
    for (std::uint64_t pulse = 0; pulse < 300; ++pulse) {
        std::vector<BeamSample> samples(1 + pulse % 61);
        const double base_m = std::pow(10.0, 4.0 * u(rng));  // 1 m to 10 km
        for (BeamSample& s : samples) {
            s.weight = u(rng);
            s.hit.range_m = base_m + 5.0 * u(rng);
            s.hit.cos_incidence = u(rng);
            s.hit.albedo = u(rng);
            const double pick = u(rng);
            if (pick < 0.05) {
                s.hit = SubRayHit{};  // a miss
            } else if (pick < 0.1) {
                s.hit.range_m = pick < 0.07 ? -1.0 : std::numeric_limits<double>::quiet_NaN();
            }
        }
        ASSERT_TRUE(powers_are_each_samples(sim, pulse, samples, r)) << "pulse " << pulse;
        for (std::size_t j = 0; j < samples.size(); ++j) {
            const double p = r.sub_ray_power_w[j];
            const SubRayHit& h = samples[j].hit;
            if (p > 0) {
                const double l = monostatic_reflectance(config.brdf, h.cos_incidence,
                                                        h.specular_weight, h.specular_exponent);
                const double exact = received_power_w(
                    config.radiometry, config.radiometry.peak_power_w * samples[j].weight, h.albedo,
                    l, h.range_m, two_way_transmission(2e-4, h.range_m));
                ASSERT_NEAR(p, exact, 2.0 * (std::nextafter(exact, 1.0) - exact));
            }
        }
    }
}

TEST(PhysicsSubRayExact, MattePowersInLanesMatchEachSampleUnderEitherBrdf) {
    // Matte samples (no specular weight) go four at a time (the reflectance is cos_i where
    // positive): grazing, back-facing and NaN incidences, misses and bad ranges among them,
    // and now and then a glossy sample (its four and the rest one by one), under both BRDFs.
    for (const Brdf brdf : {Brdf::normalized_phong, Brdf::phenomenological}) {
        PhysicsConfig config;
        config.brdf = brdf;
        const PulseSimulator sim(config);
        std::mt19937_64 rng(17);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        PulseResponse r;
        std::size_t glossy_pulses = 0;
        for (std::uint64_t pulse = 0; pulse < 400; ++pulse) {
            std::vector<BeamSample> samples(1 + pulse % 41);
            bool glossy = false;
            for (BeamSample& s : samples) {
                s.weight = u(rng);
                s.hit.range_m = 10.0 + 3000.0 * u(rng);
                s.hit.cos_incidence = 2.0 * u(rng) - 0.2;  // some <= 0, some > 1
                s.hit.albedo = u(rng);
                const double pick = u(rng);
                if (pick < 0.04) {
                    s.hit.cos_incidence = pick < 0.02 ? 0.0 : std::nan("");
                } else if (pick < 0.08) {
                    s.hit.range_m = pick < 0.06 ? -2.0 : std::numeric_limits<double>::infinity();
                } else if (pulse % 3 == 0 && pick > 0.97) {
                    s.hit.specular_weight = 0.5;
                    glossy = true;
                }
            }
            glossy_pulses += glossy ? 1 : 0;
            ASSERT_TRUE(powers_are_each_samples(sim, pulse, samples, r))
                << to_string(brdf) << " pulse " << pulse;
        }
        EXPECT_GT(glossy_pulses, 20u);
    }
}

TEST(PhysicsSubRayExact, FootprintRadiusIsHypotBitForBit) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (const double exit_m : {0.0, 0.004, 0.05}) {
        BeamConfig beam;
        beam.exit_diameter_m = exit_m;
        for (int i = 0; i < 20000; ++i) {
            beam.divergence_rad = i % 5 == 0 ? 0.0 : 0.01 * u(rng);
            const double range_m = std::pow(10.0, 5.0 * u(rng) - 1.0);
            ASSERT_EQ(footprint_radius_m(beam, range_m),
                      std::hypot(exit_m / 2.0, range_m * beam.divergence_rad / 2.0))
                << exit_m << " " << beam.divergence_rad << " " << range_m;
        }
    }
}

}  // namespace
}  // namespace beamtrace
