#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "physics/detail/fast_exp.hpp"
#include "physics/detail/fast_log.hpp"
#include "physics/ulp_support.hpp"

namespace beamtrace {
namespace {

using detail::ExpLanes;
using detail::fast_log;

/// |y - ln x| in ulps of ln x (from the 64-bit long double log, whose own error is far below a
/// double's ulp); x > 0, x != 1.
double ulp_error(double x) {
    return test::ulps_from(std::log(static_cast<long double>(x)), fast_log(x));
}

/// A fixed sequence of doubles uniform in [0, 1).
struct Uniform : test::UniformSequence {
    Uniform() : test::UniformSequence{11} {}
};

// The fit's arguments: a sample over its echo's top, in [kEchoFitFraction, 1], most near 1.
TEST(FastLog, WithinOneUlpOverTheRangeTheFitUses) {
    Uniform u;
    double worst = 0.0;
    for (int i = 0; i < 400000; ++i) {
        const double x = i % 2 == 0 ? 0.01 + 0.99 * u() : 1.0 - std::ldexp(u(), -(i % 50));
        if (x != 1.0) {
            worst = std::max(worst, ulp_error(x));
        }
    }
    EXPECT_LT(worst, 1.0);
    // Right around 1, where ln x ~ x - 1 is tiny: every double within 2000 ulps of it.
    double x = 1.0, y = 1.0;
    for (int i = 0; i < 2000; ++i) {
        x = std::nextafter(x, 0.0);
        y = std::nextafter(y, 2.0);
        worst = std::max({worst, ulp_error(x), ulp_error(y)});
    }
    EXPECT_LT(worst, 1.0);
}

TEST(FastLog, WithinOneUlpOverTheWholeRange) {
    Uniform u;
    double worst = 0.0;
    for (int i = 0; i < 400000; ++i) {
        // Normal arguments over every binade, then subnormal ones.
        const double x = i % 8 == 0
                             ? std::ldexp(1.0 + u(), -1074 + static_cast<int>(u() * 52))
                             : std::ldexp(0.5 + 0.5 * u(), -1021 + static_cast<int>(u() * 2045));
        if (x != 1.0) {
            worst = std::max(worst, ulp_error(x));
        }
    }
    EXPECT_LT(worst, 1.0);
}

TEST(FastLog, ExactWhereItMatters) {
    EXPECT_EQ(std::bit_cast<std::uint64_t>(fast_log(1.0)), 0u);  // +0
    constexpr double inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(fast_log(0.0), -inf);
    EXPECT_EQ(fast_log(-0.0), -inf);
    EXPECT_EQ(fast_log(inf), inf);
    EXPECT_TRUE(std::isnan(fast_log(-1.0)));
    EXPECT_TRUE(std::isnan(fast_log(-inf)));
    EXPECT_TRUE(std::isnan(fast_log(std::numeric_limits<double>::quiet_NaN())));
    // Powers of 2: k ln 2 rounded once (k ln2_hi exact, the rest below it).
    for (int k = -1074; k <= 1023; ++k) {
        const double want = static_cast<double>(static_cast<long double>(k) * std::log(2.0L));
        ASSERT_EQ(fast_log(std::ldexp(1.0, k)), want) << k;
    }
    EXPECT_EQ(fast_log(std::numeric_limits<double>::max()),
              std::log(std::numeric_limits<double>::max()));
    EXPECT_EQ(fast_log(std::numeric_limits<double>::denorm_min()),
              std::log(std::numeric_limits<double>::denorm_min()));
}

/// Lengths 0 to 19 and 203, normal arguments mixed with 0, subnormals, +inf and NaN.
std::vector<std::vector<double>> lane_cases() {
    Uniform u;
    std::vector<std::vector<double>> cases;
    const double odd[] = {0.0,
                          1e-310,
                          std::numeric_limits<double>::infinity(),
                          -2.0,
                          std::numeric_limits<double>::quiet_NaN(),
                          1.0};
    for (const std::size_t n : {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 13, 16, 19, 203}) {
        std::vector<double> x(n);
        for (std::size_t i = 0; i < n; ++i) {
            x[i] = i % 7 == 3 ? odd[(i / 7) % 6]
                              : std::ldexp(0.5 + u(), static_cast<int>(u() * 80) - 40);
        }
        cases.push_back(x);
    }
    return cases;
}

TEST(FastLog, EveryLanePathGivesTheScalarBits) {
    const auto cases = lane_cases();
    int paths = 0;
    const auto same = [](double a, double b) {
        return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b) ||
               (std::isnan(a) && std::isnan(b));
    };
    for (const ExpLanes path :
         {ExpLanes::scalar, ExpLanes::sse2, ExpLanes::avx2, ExpLanes::avx512}) {
        if (!detail::exp_lanes_available(path)) {
            continue;
        }
        ++paths;
        for (const std::vector<double>& x : cases) {
            std::vector<double> y(x.size() + 1, 42.0);  // the one past the end stays
            detail::fast_log_lanes(path, x.data(), y.data(), x.size());
            ASSERT_EQ(y.back(), 42.0);
            for (std::size_t i = 0; i < x.size(); ++i) {
                ASSERT_TRUE(same(y[i], fast_log(x[i])))
                    << "path " << static_cast<int>(path) << " n " << x.size() << " x " << x[i];
            }
        }
        std::vector<double> v = cases.back();  // in place
        detail::fast_log_lanes(path, v.data(), v.data(), v.size());
        for (std::size_t i = 0; i < v.size(); ++i) {
            ASSERT_TRUE(same(v[i], fast_log(cases.back()[i])));
        }
    }
    EXPECT_GE(paths, 1);
    const std::vector<double>& x = cases.back();  // the default choice is one of them
    std::vector<double> y(x.size());
    detail::fast_log_lanes(x.data(), y.data(), x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        ASSERT_TRUE(same(y[i], fast_log(x[i])));
    }
}

}  // namespace
}  // namespace beamtrace
