#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "physics/detail/fast_exp.hpp"
#include "physics/ulp_support.hpp"

namespace beamtrace {
namespace {

using detail::ExpLanes;
using detail::fast_exp;

/// |y - e^x| in ulps of e^x (e^x from the 64-bit long double exp, whose own error is below
/// 2^-11 of a double's ulp), the subnormals' ulp being 2^-1074.
double ulp_error(double x) {
    return test::ulps_from(std::exp(static_cast<long double>(x)), fast_exp(x));
}

/// A fixed sequence of doubles uniform in [0, 1).
struct Uniform : test::UniformSequence {
    Uniform() : test::UniformSequence{7} {}
};

TEST(FastExp, WithinOneUlpOverTheRangeTheWaveformUses) {
    // The waveform's exponents (Gaussians to 5 sigma and beyond, their ratios, the fits) lie in
    // [-60, 10]; densely there, and about 0 where e^x nears 1.
    double worst = 0.0, worst_x = 0.0;
    const auto check = [&](double x) {
        const double err = ulp_error(x);
        if (err > worst) {
            worst = err;
            worst_x = x;
        }
    };
    for (double x = -60.0; x < 10.0; x += 1.3e-4) {
        check(x);
    }
    for (double x = -1.0; x < 1.0; x += 6.1e-6) {
        check(x);
    }
    EXPECT_LT(worst, 1.0) << "at x = " << worst_x;
}

TEST(FastExp, WithinOneUlpOverTheWholeRange) {
    // Normal results, then subnormal ones (whose ulp is 2^-1074: the error can only shrink).
    Uniform u;
    double worst = 0.0, worst_x = 0.0;
    for (int i = 0; i < 300000; ++i) {
        const double x = -745.1 + 1454.8 * u();
        const double err = ulp_error(x);
        if (err > worst) {
            worst = err;
            worst_x = x;
        }
    }
    EXPECT_LT(worst, 1.0) << "at x = " << worst_x;
}

TEST(FastExp, ExactWhereItMatters) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(std::bit_cast<std::uint64_t>(fast_exp(0.0)), std::bit_cast<std::uint64_t>(1.0));
    EXPECT_EQ(std::bit_cast<std::uint64_t>(fast_exp(-0.0)), std::bit_cast<std::uint64_t>(1.0));
    EXPECT_EQ(fast_exp(kInf), kInf);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(fast_exp(-kInf)), 0u);  // +0
    EXPECT_TRUE(std::isnan(fast_exp(std::numeric_limits<double>::quiet_NaN())));
    EXPECT_TRUE(std::isnan(fast_exp(-std::numeric_limits<double>::quiet_NaN())));
    // Overflow and underflow where std::exp's are.
    EXPECT_EQ(fast_exp(709.79), kInf);
    EXPECT_EQ(fast_exp(1e300), kInf);
    EXPECT_TRUE(std::isfinite(fast_exp(709.78)));
    EXPECT_NEAR(fast_exp(709.78) / std::exp(709.78), 1.0, 0x1p-52);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(fast_exp(-745.2)), 0u);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(fast_exp(-1e300)), 0u);
    EXPECT_EQ(fast_exp(-745.1), std::numeric_limits<double>::denorm_min());
    EXPECT_EQ(fast_exp(-745.1), std::exp(-745.1));
    // Subnormal results: within an ulp of std::exp's (here 2^-1074, exact but for the last bit).
    for (double x = -745.0; x < -708.0; x += 0.37) {
        EXPECT_LE(std::abs(fast_exp(x) - std::exp(x)),
                  std::abs(std::nextafter(std::exp(x), kInf) - std::exp(x)))
            << x;
    }
    // Tiny arguments: 1 + x rounded (e^x's rounding there), on either side of 1.
    EXPECT_EQ(fast_exp(0x1p-60), 1.0);
    EXPECT_EQ(fast_exp(-0x1p-60), 1.0);
    EXPECT_EQ(fast_exp(0x1p-30), std::exp(0x1p-30));
    EXPECT_EQ(fast_exp(-0x1p-30), std::exp(-0x1p-30));
}

/// Lengths 0 to 40 (the blocks and their padded tails) of arguments mostly in the waveform's
/// range, some beyond the one-step range or not numbers (those blocks go lane by lane).
std::vector<std::vector<double>> lane_cases() {
    Uniform u;
    std::vector<std::vector<double>> cases;
    for (std::size_t n = 0; n <= 40; ++n) {
        for (int trial = 0; trial < 40; ++trial) {
            std::vector<double> x(n);
            for (double& v : x) {
                const double pick = u();
                v = pick < 0.03   ? std::numeric_limits<double>::quiet_NaN()
                    : pick < 0.06 ? -740.0 + 15.0 * u()
                    : pick < 0.09 ? 700.0 + 12.0 * u()
                    : pick < 0.5  ? -60.0 + 70.0 * u()
                                  : -1.0 + 2.0 * u();
            }
            cases.push_back(std::move(x));
        }
    }
    return cases;
}

TEST(FastExp, EveryLanePathGivesTheScalarBits) {
    const auto cases = lane_cases();
    int paths = 0;
    for (const ExpLanes path :
         {ExpLanes::scalar, ExpLanes::sse2, ExpLanes::avx2, ExpLanes::avx512}) {
        if (!detail::exp_lanes_available(path)) {
            continue;
        }
        ++paths;
        for (const std::vector<double>& x : cases) {
            std::vector<double> y(x.size() + 1, 42.0);  // the one past the end stays
            detail::fast_exp_lanes(path, x.data(), y.data(), x.size());
            ASSERT_EQ(y.back(), 42.0);
            for (std::size_t i = 0; i < x.size(); ++i) {
                ASSERT_EQ(std::bit_cast<std::uint64_t>(y[i]),
                          std::bit_cast<std::uint64_t>(fast_exp(x[i])))
                    << "path " << static_cast<int>(path) << " n " << x.size() << " x " << x[i];
            }
        }
        // In place, as build_waveform calls it.
        std::vector<double> v = cases.back();
        detail::fast_exp_lanes(path, v.data(), v.data(), v.size());
        for (std::size_t i = 0; i < v.size(); ++i) {
            ASSERT_EQ(std::bit_cast<std::uint64_t>(v[i]),
                      std::bit_cast<std::uint64_t>(fast_exp(cases.back()[i])));
        }
    }
    EXPECT_GE(paths, 1);
    // The default choice is one of them.
    const std::vector<double>& x = cases.back();
    std::vector<double> y(x.size());
    detail::fast_exp_lanes(x.data(), y.data(), x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(y[i]), std::bit_cast<std::uint64_t>(fast_exp(x[i])));
    }
}

}  // namespace
}  // namespace beamtrace
