#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "beamtrace/physics/noise.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "physics/sample_stats.hpp"

namespace beamtrace {
namespace {

using Stats = test::SampleStats;

Stats stats(const std::vector<double>& v) {
    return test::sample_stats(v);
}

/// A single ray on a plane facing the sensor at `range_m`.
std::vector<SubRayHit> facing_plane(double range_m) {
    SubRayHit h;
    h.range_m = range_m;
    h.cos_incidence = 1.0;
    h.albedo = 0.5;
    return {h};
}

// Acceptance: over 1e5 pulses the range error has a standard deviation within 3 % of sigma and
// a mean within 4 standard errors of 0; with sigma = sqrt(a^2 + (b R)^2) too.
TEST(PhysicsNoise, RangeNoiseStatisticsThroughThePulse) {
    for (const auto& [a, b] : {std::pair{0.02, 0.0}, std::pair{0.01, 2e-4}}) {
        PhysicsConfig c;
        c.noise.range_sigma_m = a;
        c.noise.range_sigma_per_m = b;
        const PulseSimulator sim(c);
        const double range = 100.0;
        const double sigma = std::hypot(a, b * range);
        EXPECT_DOUBLE_EQ(range_sigma_m(c.noise, range), sigma);
        PhysicsConfig quiet = c;
        quiet.noise = {};
        const double truth = simulate_pulse(quiet, 3, 0, facing_plane(range)).returns.at(0).range_m;
        EXPECT_NEAR(truth, range, 1e-6);
        constexpr int kN = 100'000;
        std::vector<double> err;
        err.reserve(kN);
        PulseResponse r;
        const auto hits = facing_plane(range);
        for (int i = 0; i < kN; ++i) {
            sim.simulate(3, static_cast<std::uint64_t>(i), hits, r);
            ASSERT_EQ(r.returns.size(), 1u);
            err.push_back(r.returns[0].range_m - truth);
        }
        const Stats s = stats(err);
        EXPECT_NEAR(s.std, sigma, 0.03 * sigma) << a << " + " << b << " R";
        EXPECT_NEAR(s.mean, 0.0, 4 * sigma / std::sqrt(kN));
    }
}

TEST(PhysicsNoise, DeterministicPerSeedAndPulseWhateverTheOrder) {
    PhysicsConfig c;
    c.noise.range_sigma_m = 0.05;
    c.noise.dropout_probability = 0.2;
    const PulseSimulator sim(c);
    const auto hits = facing_plane(30.0);
    std::vector<double> fwd, bwd(200);
    PulseResponse r;
    for (std::uint64_t i = 0; i < 200; ++i) {
        sim.simulate(11, i, hits, r);
        fwd.push_back(r.dropped ? -1.0 : r.returns.at(0).range_m);
    }
    for (std::uint64_t i = 200; i-- > 0;) {
        sim.simulate(11, i, hits, r);
        bwd[i] = r.dropped ? -1.0 : r.returns.at(0).range_m;
    }
    EXPECT_EQ(fwd, bwd);
    sim.simulate(12, 0, hits, r);
    sim.simulate(11, 0, hits, r);
    EXPECT_EQ(r.dropped ? -1.0 : r.returns.at(0).range_m, fwd[0]);
    int differ = 0;
    for (std::uint64_t i = 0; i < 200; ++i) {
        sim.simulate(12, i, hits, r);
        differ += (r.dropped ? -1.0 : r.returns.at(0).range_m) != fwd[i] ? 1 : 0;
    }
    EXPECT_GT(differ, 150);  // another seed, other numbers
}

TEST(PhysicsNoise, DropoutRate) {
    NoiseConfig c;
    c.dropout_probability = 0.1;
    constexpr int kN = 100'000;
    int dropped = 0;
    for (int i = 0; i < kN; ++i) {
        dropped += pulse_dropped(c, 5, static_cast<std::uint64_t>(i)) ? 1 : 0;
    }
    EXPECT_NEAR(dropped / double{kN}, 0.1, 4 * std::sqrt(0.1 * 0.9 / kN));
    c.dropout_probability = 0;
    EXPECT_FALSE(pulse_dropped(c, 5, 0));
    c.dropout_probability = 1;
    EXPECT_TRUE(pulse_dropped(c, 5, 0));
    PhysicsConfig pc;
    pc.noise.dropout_probability = 1;
    const PulseResponse r = simulate_pulse(pc, 1, 0, facing_plane(10));
    EXPECT_TRUE(r.dropped);
    EXPECT_TRUE(r.returns.empty());
}

TEST(PhysicsNoise, AngularJitterHasTheRightSpread) {
    NoiseConfig c;
    c.angle_jitter_rad = 1e-3;
    const Vec3d axis = normalize(Vec3d{1, 2, -3});
    constexpr int kN = 100'000;
    std::vector<double> along_e1;
    double sum_sq = 0;
    Vec3d e1, e2;
    orthonormal_basis(axis, e1, e2);
    for (int i = 0; i < kN; ++i) {
        const Vec3d d = jitter_direction(c, 2, static_cast<std::uint64_t>(i), axis);
        ASSERT_NEAR(length(d), 1.0, 1e-12);
        const double ang = std::acos(std::min(1.0, dot(d, axis)));
        sum_sq += ang * ang;
        along_e1.push_back(std::atan2(dot(d, e1), dot(d, axis)));
    }
    // Two independent N(0, s) tilts: E[angle^2] = 2 s^2; each component has std s.
    EXPECT_NEAR(std::sqrt(sum_sq / kN), std::sqrt(2.0) * 1e-3, 0.03 * std::sqrt(2.0) * 1e-3);
    const Stats s = stats(along_e1);
    EXPECT_NEAR(s.std, 1e-3, 0.03e-3);
    EXPECT_NEAR(s.mean, 0.0, 4e-3 / std::sqrt(kN));
    c.angle_jitter_rad = 0;
    EXPECT_EQ(jitter_direction(c, 2, 0, axis), axis);
}

}  // namespace
}  // namespace beamtrace
