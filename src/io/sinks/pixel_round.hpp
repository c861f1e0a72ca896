// Rounding of a pixel's channel value, as std::lround() rounds it, without the library call.
#pragma once

#include <cstdint>

namespace beamtrace::detail {

/// std::lround(v) for a finite v in [0, 2^63): halves away from zero. The truncation i is a whole
/// double no greater than v, and v - i (the fraction) is exact: below 1, v's bits are all
/// fraction; from 1 on, i has v's exponent or less and the difference fits v's mantissa. So the
/// comparison with 0.5 sees the true fraction, where v + 0.5 could round up (0.49999999999999994).
[[nodiscard]] inline std::int64_t round_half_up(double v) {
    const auto i = static_cast<std::int64_t>(v);
    return i + static_cast<std::int64_t>(v - static_cast<double>(i) >= 0.5);
}

}  // namespace beamtrace::detail
