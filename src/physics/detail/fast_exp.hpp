// e^x of our own, the same bits in scalar code and in SIMD lanes (physics' private helper).
//
// x = k ln 2 + r with k = round(x / ln 2) and |r| <= ln 2 / 2 (Cody and Waite: ln 2 in two
// parts, the first of 32 bits so that k ln2_hi is exact); e^r = 1 + r + r^2 q(r), q a degree-9
// Chebyshev fit of (e^r - 1 - r) / r^2 on [-0.35, 0.35] (scripts/exp_coefficients.py) evaluated
// by Estrin's scheme; then 2^k by the exponent's bits. Only IEEE additions, multiplications and
// integer operations in one fixed order (the file is built without FMA contraction): every path,
// scalar, SSE2, AVX2 and AVX-512, rounds every step alike. Error below 1 ulp (0.98 at most in
// 4.8e7 random arguments, 0.94 in the tests' sweeps: tests/physics/fast_exp_test.cpp); exactly 1
// at 0, +inf above ln(DBL_MAX), 0 below -745.2 (subnormal results between), NaN for NaN.
#pragma once

#include <cstddef>

namespace beamtrace::detail {

/// e^x as described above.
[[nodiscard]] double fast_exp(double x);

/// The paths of fast_exp_lanes.
enum class ExpLanes { scalar, sse2, avx2, avx512 };

/// True when this CPU (and build) runs `path`.
[[nodiscard]] bool exp_lanes_available(ExpLanes path);

/// y[i] = fast_exp(x[i]) for i < n, bit for bit, by the widest path this CPU runs (x == y allowed).
void fast_exp_lanes(const double* x, double* y, std::size_t n);

/// The same by `path` (exp_lanes_available(path) must hold).
void fast_exp_lanes(ExpLanes path, const double* x, double* y, std::size_t n);

}  // namespace beamtrace::detail
