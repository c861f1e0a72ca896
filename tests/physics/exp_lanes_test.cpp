#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "physics/detail/exp_lanes.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// exp_lanes(x) against std::exp(x), bit for bit; the count of differing elements.
std::size_t mismatches(const std::vector<double>& x) {
    std::vector<double> y(x.size());
    detail::exp_lanes(x.data(), y.data(), x.size());
    std::size_t bad = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double e = std::exp(x[i]);
        const bool same = std::bit_cast<std::uint64_t>(y[i]) == std::bit_cast<std::uint64_t>(e) ||
                          (std::isnan(y[i]) && std::isnan(e));
        bad += same ? 0 : 1;
    }
    return bad;
}

TEST(ExpLanes, BitForBitStdExpOnTheWaveformsArguments) {
    // The waveform's exponents: -(d/sigma)^2 / 2 down to about -15, ratios and steps near 0,
    // and a uniform spread over the whole fast range, 2^20 of them (odd counts: the tail too).
    std::vector<double> x;
    std::uint64_t s = 12345;
    const auto next = [&s] {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(s >> 11) * 0x1p-53;
    };
    for (int i = 0; i < (1 << 20) + 3; ++i) {
        const double u = next();
        switch (i % 4) {
            case 0:
                x.push_back(-15.0 * u);
                break;
            case 1:
                x.push_back(0.1 * (u - 0.5));
                break;
            case 2:
                x.push_back(1400.0 * (u - 0.5));
                break;
            default:
                x.push_back(std::ldexp(u - 0.5, static_cast<int>(s % 70) - 60));
                break;
        }
    }
    EXPECT_EQ(mismatches(x), 0u);
}

TEST(ExpLanes, SpecialArgumentsCallStdExp) {
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<double> x = {0.0,    -0.0,   0x1p-60, -0x1p-55, 0x1p-54,      511.9,  -511.9,
                                   512.0,  -512.0, 709.7,   709.8,    -745.0,       -745.2, -708.5,
                                   -800.0, 1e300,  inf,     -inf,     std::nan(""), 1.0,    -1.0};
    EXPECT_EQ(mismatches(x), 0u);
    std::vector<double> y(x.size());
    detail::exp_lanes(x.data(), y.data(), x.size());
    EXPECT_EQ(y[0], 1.0);
    EXPECT_EQ(y[16], inf);
    EXPECT_EQ(y[17], 0.0);
    EXPECT_TRUE(std::isnan(y[18]));
    EXPECT_EQ(y[19], std::exp(1.0));
}

TEST(ExpLanes, InPlaceAndShortCounts) {
    for (std::size_t n = 0; n < 11; ++n) {
        std::vector<double> x(n), want(n);
        for (std::size_t i = 0; i < n; ++i) {
            x[i] = -0.37 * static_cast<double>(i) - 0.01;
            want[i] = std::exp(x[i]);
        }
        detail::exp_lanes(x.data(), x.data(), n);
        for (std::size_t i = 0; i < n; ++i) {
            EXPECT_EQ(std::bit_cast<std::uint64_t>(x[i]), std::bit_cast<std::uint64_t>(want[i]));
        }
    }
}

TEST(ExpLanes, LanesOnWhereTheCpuHasAvx2AndFma) {
#if defined(__x86_64__) && defined(__GNUC__) && defined(__GLIBC__)
    // On glibc with AVX2 and FMA the lanes replicate its exp: they must be on (the survey's
    // speed depends on it); elsewhere they may be off, never wrong (the tests above).
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        EXPECT_TRUE(detail::exp_lanes_vectorised());
    }
#else
    BEAMTRACE_SKIP_HARDWARE("lanes only on x86-64 with GCC-style builtins");
#endif
}

}  // namespace
}  // namespace beamtrace
