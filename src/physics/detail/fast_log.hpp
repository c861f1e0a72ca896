// ln x of our own, the same bits in scalar code and in SIMD lanes (physics' private helper;
// built in fast_exp.cpp, with fast_exp's flags and lanes).
//
// x = 2^k m with m in [sqrt(2)/2, sqrt(2)) by integer operations on x's bits, f = m - 1 (exact),
// s = f / (2 + f): ln(1 + f) = 2 atanh(s) = f - f^2/2 + s (f^2/2 + R(z)), z = s^2, |s| < 0.172,
// R(z) = z p(z), p a degree-7 Chebyshev fit (scripts/log_coefficients.py) evaluated by Estrin's
// scheme; then k ln 2 added in two parts (fast_exp's: k ln2_hi exact). Only IEEE additions,
// multiplications, one division and integer operations in one fixed order (no FMA contraction):
// every path, scalar, SSE2, AVX2 and AVX-512, rounds every step alike. Error below 1 ulp against
// long double (tests/physics/fast_log_test.cpp); exactly 0 at 1, -inf at +-0, NaN below 0 and
// for NaN, +inf at +inf, subnormals as 2^-54 times a normal.
#pragma once

#include <cstddef>

#include "physics/detail/fast_exp.hpp"

namespace beamtrace::detail {

/// ln x as described above.
[[nodiscard]] double fast_log(double x);

/// y[i] = fast_log(x[i]) for i < n, bit for bit, by the widest path this CPU runs (x == y
/// allowed).
void fast_log_lanes(const double* x, double* y, std::size_t n);

/// The same by `path` (exp_lanes_available(path) must hold: the paths are fast_exp's).
void fast_log_lanes(ExpLanes path, const double* x, double* y, std::size_t n);

}  // namespace beamtrace::detail
