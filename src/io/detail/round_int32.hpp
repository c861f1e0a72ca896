// Rounding to int32 as std::round / std::lround round (halves away from zero), without the
// library call: the LAS writer's coordinates and scan angles, the preview's pixel channels.
#pragma once

#include <cstdint>

namespace beamtrace::detail {

/// std::round (halves away from zero) for |x| < 2^31, without a library call: truncation is one
/// instruction, and x - trunc(x) is exact in that range (so 0.49999999999999994 rounds to 0,
/// where x + 0.5 would round up).
[[nodiscard]] inline std::int32_t round_to_int32(double x) {
    const auto i = static_cast<std::int32_t>(x);
    const double f = x - static_cast<double>(i);
    return i + (f >= 0.5 ? 1 : 0) - (f <= -0.5 ? 1 : 0);
}

/// True when std::round(x) fits in an int32 (false for NaN).
[[nodiscard]] inline bool rounds_into_int32(double x) {
    return x > -2147483648.5 && x < 2147483647.5;
}

}  // namespace beamtrace::detail
