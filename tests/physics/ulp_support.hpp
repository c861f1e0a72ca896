// Helpers of the tests of our own exp and log: errors in ulps and a fixed sequence of doubles.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace beamtrace::test {

/// |y - ref| in ulps of the double nearest ref (ref from a long double function, whose own error
/// is far below a double's ulp), the subnormals' ulp being 2^-1074.
inline double ulps_from(long double ref, double y) {
    int e = 0;
    std::frexp(ref, &e);  // |ref| = m 2^e, 0.5 <= m < 1
    const long double ulp = std::ldexp(1.0L, std::max(e - 53, -1074));
    return static_cast<double>(std::abs(static_cast<long double>(y) - ref) / ulp);
}

/// A fixed sequence of doubles uniform in [0, 1) (a 64-bit LCG's top 53 bits).
struct UniformSequence {
    std::uint64_t s;
    double operator()() {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(s >> 11) * 0x1p-53;
    }
};

}  // namespace beamtrace::test
