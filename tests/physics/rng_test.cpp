#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "beamtrace/core/rng.hpp"

namespace beamtrace {
namespace {

// Known-answer vectors of Random123's kat_vectors for philox4x32 with 10 rounds.
TEST(CounterRng, PhiloxKnownAnswers) {
    using A4 = std::array<std::uint32_t, 4>;
    EXPECT_EQ(philox4x32({0, 0, 0, 0}, {0, 0}),
              (A4{0x6627e8d5u, 0xe169c58du, 0xbc57ac4cu, 0x9b00dbd8u}));
    EXPECT_EQ(philox4x32({0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu},
                         {0xffffffffu, 0xffffffffu}),
              (A4{0x408f276du, 0x41c83b0eu, 0xa20bc7c6u, 0x6d5451fdu}));
    EXPECT_EQ(philox4x32({0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u},
                         {0xa4093822u, 0x299f31d0u}),
              (A4{0xd16cfe09u, 0x94fdccebu, 0x5001e420u, 0x24126ea1u}));
}

TEST(CounterRng, SameKeySameSequenceWhateverTheOrder) {
    // Pulses drawn forwards and backwards give identical numbers.
    std::vector<double> fwd(1000), bwd(1000);
    for (std::size_t i = 0; i < fwd.size(); ++i) {
        CounterRng rng(42, i, 3, RngStream::range_noise);
        fwd[i] = rng.normal();
    }
    for (std::size_t i = bwd.size(); i-- > 0;) {
        CounterRng rng(42, i, 3, RngStream::range_noise);
        bwd[i] = rng.normal();
    }
    EXPECT_EQ(fwd, bwd);
}

TEST(CounterRng, KeysAreIndependent) {
    const auto first = [](std::uint64_t seed, std::uint64_t pulse, std::uint32_t sub, RngStream s) {
        return CounterRng(seed, pulse, sub, s).next_u32();
    };
    const std::uint32_t base = first(1, 7, 0, RngStream::range_noise);
    EXPECT_NE(base, first(2, 7, 0, RngStream::range_noise));
    EXPECT_NE(base, first(1, 8, 0, RngStream::range_noise));
    EXPECT_NE(base, first(1, 7, 1, RngStream::range_noise));
    EXPECT_NE(base, first(1, 7, 0, RngStream::dropout));
    EXPECT_NE(base, first(1, 7 + (std::uint64_t{1} << 32), 0, RngStream::range_noise));
    EXPECT_NE(base, first(1 + (std::uint64_t{1} << 32), 7, 0, RngStream::range_noise));
}

TEST(CounterRng, UniformMomentsAndHistogram) {
    constexpr int kN = 200'000;
    constexpr int kBins = 20;
    std::array<int, kBins> hist{};
    double sum = 0, sum2 = 0;
    for (int i = 0; i < kN; ++i) {
        CounterRng rng(9, static_cast<std::uint64_t>(i), 0, RngStream::user);
        const double u = rng.uniform();
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        sum += u;
        sum2 += u * u;
        ++hist[static_cast<std::size_t>(u * kBins)];
    }
    const double mean = sum / kN, var = sum2 / kN - mean * mean;
    EXPECT_NEAR(mean, 0.5, 4 * std::sqrt(1.0 / 12.0 / kN));
    EXPECT_NEAR(var, 1.0 / 12.0, 0.01 / 12.0);
    // Chi-square with 19 degrees of freedom: the 99.9th percentile is 43.8.
    double chi2 = 0;
    for (const int h : hist) {
        const double expected = static_cast<double>(kN) / kBins;
        chi2 += (h - expected) * (h - expected) / expected;
    }
    EXPECT_LT(chi2, 43.8);
}

TEST(CounterRng, NormalMoments) {
    constexpr int kN = 200'000;
    double s1 = 0, s2 = 0, s4 = 0;
    int beyond2 = 0;
    CounterRng rng(5, 0, 0, RngStream::user);  // one long stream: exercises block refills
    for (int i = 0; i < kN; ++i) {
        const double g = rng.normal();
        s1 += g;
        s2 += g * g;
        s4 += g * g * g * g;
        beyond2 += std::abs(g) > 2.0 ? 1 : 0;
    }
    EXPECT_NEAR(s1 / kN, 0.0, 4.0 / std::sqrt(kN));
    EXPECT_NEAR(s2 / kN, 1.0, 0.015);
    EXPECT_NEAR(s4 / kN, 3.0, 0.1);
    // P(|g| > 2) = 0.0455.
    EXPECT_NEAR(static_cast<double>(beyond2) / kN, 0.0455, 0.003);
}

}  // namespace
}  // namespace beamtrace
