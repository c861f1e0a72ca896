#include "physics/detail/fast_exp.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "physics/detail/fast_log.hpp"

// Every path must round each product and sum alone (cmake/BeamtraceModules.cmake).
#ifndef BEAMTRACE_FP_CONTRACT_OFF
#error "fast_exp.cpp must be compiled with -ffp-contract=off"
#endif

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#include <immintrin.h>
#define BEAMTRACE_EXP_LANES 1
#endif

namespace beamtrace::detail {
namespace {

// The constants as scripts/exp_coefficients.py derives them.
constexpr double kLog2e = 0x1.71547652b82fep+0;    // 1 / ln 2
constexpr double kLn2Hi = 0x1.62e42ff000000p-1;    // ln 2 to 32 bits: k kLn2Hi is exact
constexpr double kLn2Lo = -0x1.718432a1b0e26p-35;  // ln 2 - kLn2Hi
/// y + kShifter rounds y (|y| < 2^51) to an integer k held in the low bits of the sum.
constexpr double kShifter = 0x1.8p52;
/// q(r) = sum kQ[i] r^i ~ (e^r - 1 - r) / r^2 on [-0.35, 0.35].
constexpr double kQ[10] = {0x1.0000000000001p-1,  0x1.5555555555556p-3,  0x1.5555555553b72p-5,
                           0x1.111111111091ap-7,  0x1.6c16c1794bd5cp-10, 0x1.a01a01a83a3a3p-13,
                           0x1.a019b62aaa671p-16, 0x1.71de0be80e7e8p-19, 0x1.2894eb03786e2p-22,
                           0x1.af3cd7b3560d9p-26};
/// For |x| below this, |k| <= 1021 and e^x is normal: 2^k is added to the exponent at once.
constexpr double kOneStepRange = 707.0;

/// The reduction and the polynomial, for a double or a vector of them: t = k + kShifter and
/// p = e^r, so that e^x = p 2^k.
template <typename V>
[[gnu::always_inline]] inline void reduce(const V& x, V& t, V& p) {
    t = x * kLog2e + kShifter;
    const V k = t - kShifter;
    // r = rh - c; the correction c joins the small terms before they are added to rh.
    const V rh = x - k * kLn2Hi, c = k * kLn2Lo, r = rh - c;
    // q by Estrin's scheme: a shorter chain of dependent operations than Horner's.
    const V r2 = r * r, r4 = r2 * r2;
    const V p01 = kQ[0] + kQ[1] * r, p23 = kQ[2] + kQ[3] * r, p45 = kQ[4] + kQ[5] * r;
    const V p67 = kQ[6] + kQ[7] * r, p89 = kQ[8] + kQ[9] * r;
    const V q = (p01 + r2 * p23) + r4 * ((p45 + r2 * p67) + r4 * p89);
    p = 1.0 + (rh + (r2 * q - c));
}

// (__builtin_bit_cast: std::bit_cast would return a vector by value from a function compiled
// for the default target, which GCC warns changes the ABI.)

/// p 2^k (t as reduce gives it) where |k| <= 1021: k added to p's exponent field (the low bits
/// of t hold k; shifted by 52, the rest of t falls off).
template <typename V, typename U>
[[gnu::always_inline]] inline void scale_once(const V& p, const V& t, V& e) {
    e = __builtin_bit_cast(V, __builtin_bit_cast(U, p) + (__builtin_bit_cast(U, t) << 52));
}

/// ln: p(z) = sum kP[i] z^i ~ (2 atanh(s) - 2s) / s^3, z = s^2 <= 0.0295
/// (scripts/log_coefficients.py).
constexpr double kP[8] = {0x1.5555555555555p-1, 0x1.9999999999a39p-2, 0x1.2492492476a1ap-2,
                          0x1.c71c7201a55d7p-3, 0x1.745cf8e4bba1bp-3, 0x1.3b1c3c1c81c8fp-3,
                          0x1.0fbde0f4ad17bp-3, 0x1.0c0aff044a970p-3};
/// The bits of sqrt(2)/2 rounded: x's bits less these have k in their top 12 bits (two's
/// complement) and, with those cleared from x's exponent, leave m in [sqrt(2)/2, sqrt(2)).
constexpr std::uint64_t kLogOffset = 0x3fe6a09e667f3bcd;
constexpr std::uint64_t kTopTwelve = 0xfff0000000000000;
constexpr std::uint64_t kSignBit = 0x8000000000000000;
/// The bits of 2^52: an integer j < 2^52 or-ed into them is the double 2^52 + j.
constexpr std::uint64_t kTwo52Bits = 0x4330000000000000;
/// k + 2048 lies in [0, 4096): 2^52 + (k + 2048) less this is k.
constexpr double kTwo52K = 0x1p52 + 2048.0;

/// For the bits of a positive normal x = 2^k m (m in [sqrt(2)/2, sqrt(2))): kd = k and
/// f = m - 1 (exact: m within a factor 2 of 1).
template <typename V, typename U>
[[gnu::always_inline]] inline void log_reduce(const U& bits, V& kd, V& f) {
    const U u = bits - kLogOffset;
    kd = __builtin_bit_cast(V, ((u ^ kSignBit) >> 52) | kTwo52Bits) - kTwo52K;
    f = __builtin_bit_cast(V, bits - (u & kTopTwelve)) - 1.0;
}

/// k ln 2 + ln(1 + f) by the series in s (detail/fast_log.hpp).
template <typename V>
[[gnu::always_inline]] inline void log_of_reduced(const V& kd, const V& f, V& y) {
    const V s = f / (2.0 + f);
    const V z = s * s, z2 = z * z, z4 = z2 * z2;
    const V p01 = kP[0] + kP[1] * z, p23 = kP[2] + kP[3] * z;
    const V p45 = kP[4] + kP[5] * z, p67 = kP[6] + kP[7] * z;
    const V r = z * ((p01 + z2 * p23) + z4 * (p45 + z2 * p67));
    const V hfsq = 0.5 * f * f;
    y = kd * kLn2Hi - ((hfsq - (s * (hfsq + r) + kd * kLn2Lo)) - f);
}

/// 2^k for -1022 <= k <= 1023.
double two_to(std::int64_t k) {
    return std::bit_cast<double>(static_cast<std::uint64_t>(k + 1023) << 52);
}

#if BEAMTRACE_EXP_LANES
constexpr std::int64_t kAbsMask = 0x7fffffffffffffff;

using Pair = double __attribute__((vector_size(16)));
using PairBits = std::uint64_t __attribute__((vector_size(16)));
using Quad = double __attribute__((vector_size(32)));
using QuadBits = std::uint64_t __attribute__((vector_size(32)));
using Oct = double __attribute__((vector_size(64)));
using OctBits = std::uint64_t __attribute__((vector_size(64)));

/// True when every lane of v is below kOneStepRange in magnitude (false for a NaN).
inline bool all_near(const Pair& v) {
    const __m128d a = _mm_and_pd(v, reinterpret_cast<__m128d>(_mm_set1_epi64x(kAbsMask)));
    return _mm_movemask_pd(_mm_cmplt_pd(a, _mm_set1_pd(kOneStepRange))) == 0x3;
}
__attribute__((target("avx2"))) inline bool all_near(const Quad& v) {
    const __m256d a = _mm256_and_pd(v, reinterpret_cast<__m256d>(_mm256_set1_epi64x(kAbsMask)));
    return _mm256_movemask_pd(_mm256_cmp_pd(a, _mm256_set1_pd(kOneStepRange), _CMP_LT_OQ)) == 0xf;
}
__attribute__((target("avx512f"))) inline bool all_near(const Oct& v) {
    const __m512d a = _mm512_abs_pd(v);
    return _mm512_cmp_pd_mask(a, _mm512_set1_pd(kOneStepRange), _CMP_LT_OQ) == 0xff;
}

/// True when every lane of v is a positive normal number (false for 0, a subnormal, +inf, NaN).
inline bool all_normal(const Pair& v) {
    const __m128d lo = _mm_cmpge_pd(v, _mm_set1_pd(std::numeric_limits<double>::min()));
    const __m128d hi = _mm_cmple_pd(v, _mm_set1_pd(std::numeric_limits<double>::max()));
    return _mm_movemask_pd(_mm_and_pd(lo, hi)) == 0x3;
}
__attribute__((target("avx2"))) inline bool all_normal(const Quad& v) {
    const __m256d lo =
        _mm256_cmp_pd(v, _mm256_set1_pd(std::numeric_limits<double>::min()), _CMP_GE_OQ);
    const __m256d hi =
        _mm256_cmp_pd(v, _mm256_set1_pd(std::numeric_limits<double>::max()), _CMP_LE_OQ);
    return _mm256_movemask_pd(_mm256_and_pd(lo, hi)) == 0xf;
}
__attribute__((target("avx512f"))) inline bool all_normal(const Oct& v) {
    const __mmask8 lo =
        _mm512_cmp_pd_mask(v, _mm512_set1_pd(std::numeric_limits<double>::min()), _CMP_GE_OQ);
    const __mmask8 hi =
        _mm512_cmp_pd_mask(v, _mm512_set1_pd(std::numeric_limits<double>::max()), _CMP_LE_OQ);
    return (lo & hi) == 0xff;
}

// The first n < w lanes (the others 0) from x, and back to y.
inline void load_first(const double* x, std::size_t, Pair& v) {
    v = Pair{x[0], 0.0};  // n is 1
}
inline void store_first(double* y, std::size_t, const Pair& e) {
    y[0] = e[0];
}
__attribute__((target("avx2"))) inline __m256i first_lanes(std::size_t n) {
    return _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<std::int64_t>(n)),
                              _mm256_setr_epi64x(0, 1, 2, 3));
}
__attribute__((target("avx2"))) inline void load_first(const double* x, std::size_t n, Quad& v) {
    v = _mm256_maskload_pd(x, first_lanes(n));
}
__attribute__((target("avx2"))) inline void store_first(double* y, std::size_t n, const Quad& e) {
    _mm256_maskstore_pd(y, first_lanes(n), e);
}
__attribute__((target("avx512f"))) inline void load_first(const double* x, std::size_t n, Oct& v) {
    v = _mm512_maskz_loadu_pd(static_cast<__mmask8>((1u << n) - 1u), x);
}
__attribute__((target("avx512f"))) inline void store_first(double* y, std::size_t n, const Oct& e) {
    _mm512_mask_storeu_pd(y, static_cast<__mmask8>((1u << n) - 1u), e);
}

/// e = fast_exp of every lane of v: at once where every |v| < kOneStepRange, else lane by lane.
template <typename V, typename U>
inline void exp_of_lanes(const V& v, V& e) {
    constexpr std::size_t w = sizeof(V) / sizeof(double);
    if (!all_near(v)) {
        for (std::size_t i = 0; i < w; ++i) {
            e[i] = fast_exp(v[i]);
        }
        return;
    }
    V t, p;
    reduce(v, t, p);
    scale_once<V, U>(p, t, e);
}

/// e = fast_log of every lane of v: at once where every lane is a positive normal number, else
/// lane by lane.
template <typename V, typename U>
inline void log_of_lanes(const V& v, V& e) {
    constexpr std::size_t w = sizeof(V) / sizeof(double);
    if (!all_normal(v)) {
        for (std::size_t i = 0; i < w; ++i) {
            e[i] = fast_log(v[i]);
        }
        return;
    }
    V kd, f;
    log_reduce<V, U>(__builtin_bit_cast(U, v), kd, f);
    log_of_reduced(kd, f, e);
}

/// Our exp (kLog false) or log (true) of one double, or of V's lanes.
template <bool kLog>
inline double one_of(double x) {
    return kLog ? fast_log(x) : fast_exp(x);
}
template <typename V, typename U, bool kLog>
inline void lanes_of(const V& v, V& e) {
    if constexpr (kLog) {
        log_of_lanes<V, U>(v, e);
    } else {
        exp_of_lanes<V, U>(v, e);
    }
}

/// Up to this many exps are taken one by one (a single ray's pulse: 3 and 1): a vector's
/// masked load and store cost more (rdtsc, AMD EPYC: 58 ticks against 76 for 1 to 3, 62
/// against 75 for 5, 85 against 76 for 7).
constexpr std::size_t kFewScalar = 4;

/// y[0, n) = fast_exp(x[0, n)) (fast_log where kLog) in blocks of V's lanes; the last block ends at
/// n (it overlaps the one before it, from inputs read before any output is written: x may be y).
template <typename V, typename U, bool kLog = false>
inline void exp_array(const double* x, double* y, std::size_t n) {
    constexpr std::size_t w = sizeof(V) / sizeof(double);
    V v = {}, e = {};
    if (n <= kFewScalar) {  // each exp's chain alone, in flight together: sooner done
        for (std::size_t i = 0; i < n; ++i) {
            y[i] = one_of<kLog>(x[i]);
        }
        return;
    }
    if (n < w) {
        load_first(x, n, v);
        lanes_of<V, U, kLog>(v, e);
        store_first(y, n, e);
        return;
    }
    V last = {};
    std::memcpy(&last, x + n - w, sizeof last);
    for (std::size_t i = 0; i + w < n; i += w) {
        std::memcpy(&v, x + i, sizeof v);
        lanes_of<V, U, kLog>(v, e);
        std::memcpy(y + i, &e, sizeof e);
    }
    lanes_of<V, U, kLog>(last, e);
    std::memcpy(y + n - w, &e, sizeof e);
}

// flatten: everything inlined into each entry, compiled for its target (the helpers above are
// not, for the default target's template bodies could not inline the AVX ones).
__attribute__((flatten)) void exp_sse2(const double* x, double* y, std::size_t n) {
    exp_array<Pair, PairBits>(x, y, n);
}
__attribute__((target("avx2"), flatten)) void exp_avx2(const double* x, double* y, std::size_t n) {
    exp_array<Quad, QuadBits>(x, y, n);
}
__attribute__((target("avx512f"), flatten)) void exp_avx512(const double* x, double* y,
                                                            std::size_t n) {
    exp_array<Oct, OctBits>(x, y, n);
}
__attribute__((flatten)) void log_sse2(const double* x, double* y, std::size_t n) {
    exp_array<Pair, PairBits, true>(x, y, n);
}
__attribute__((target("avx2"), flatten)) void log_avx2(const double* x, double* y, std::size_t n) {
    exp_array<Quad, QuadBits, true>(x, y, n);
}
__attribute__((target("avx512f"), flatten)) void log_avx512(const double* x, double* y,
                                                            std::size_t n) {
    exp_array<Oct, OctBits, true>(x, y, n);
}
#endif

void exp_scalar(const double* x, double* y, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        y[i] = fast_exp(x[i]);
    }
}

void log_scalar(const double* x, double* y, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        y[i] = fast_log(x[i]);
    }
}

}  // namespace

double fast_exp(double x) {
    double t = 0.0, p = 0.0;
    if (std::abs(x) < kOneStepRange) {
        reduce(x, t, p);
        double e = 0.0;
        scale_once<double, std::uint64_t>(p, t, e);
        return e;
    }
    if (std::isnan(x)) {
        return x + x;  // quiet, as std::exp's
    }
    // Beyond these the result is +inf or 0 alike; between, 2^k in two normal factors: the
    // first product is exact, the second rounds once (to a subnormal, 0 or +inf).
    reduce(std::clamp(x, -746.0, 710.0), t, p);
    const auto k = static_cast<std::int64_t>(t - kShifter);
    return p * two_to(k / 2) * two_to(k - k / 2);
}

double fast_log(double x) {
    double kd = 0.0, f = 0.0, y = 0.0;
    if (x >= std::numeric_limits<double>::min() && x <= std::numeric_limits<double>::max()) {
        log_reduce(std::bit_cast<std::uint64_t>(x), kd, f);
        log_of_reduced(kd, f, y);
        return y;
    }
    if (std::isnan(x)) {
        return x + x;  // quiet, as std::log's
    }
    if (x == 0) {
        return -std::numeric_limits<double>::infinity();
    }
    if (x < 0) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    if (x > 1) {
        return x;  // +inf
    }
    // A subnormal: x 2^54 is normal (the product exact), its k less 54.
    log_reduce(std::bit_cast<std::uint64_t>(x * 0x1p54), kd, f);
    log_of_reduced(kd - 54.0, f, y);
    return y;
}

bool exp_lanes_available(ExpLanes path) {
    switch (path) {
        case ExpLanes::scalar:
            return true;
#if BEAMTRACE_EXP_LANES
        case ExpLanes::sse2:
            return true;
        case ExpLanes::avx2:
            return __builtin_cpu_supports("avx2");
        case ExpLanes::avx512:
            return __builtin_cpu_supports("avx512f");
#endif
        default:
            return false;
    }
}

void fast_exp_lanes(const double* x, double* y, std::size_t n) {
#if BEAMTRACE_EXP_LANES
    if (__builtin_cpu_supports("avx512f")) {
        exp_avx512(x, y, n);
    } else if (__builtin_cpu_supports("avx2")) {
        exp_avx2(x, y, n);
    } else {
        exp_sse2(x, y, n);
    }
#else
    exp_scalar(x, y, n);
#endif
}

void fast_exp_lanes(ExpLanes path, const double* x, double* y, std::size_t n) {
    switch (path) {
#if BEAMTRACE_EXP_LANES
        case ExpLanes::sse2:
            exp_sse2(x, y, n);
            return;
        case ExpLanes::avx2:
            exp_avx2(x, y, n);
            return;
        case ExpLanes::avx512:
            exp_avx512(x, y, n);
            return;
#endif
        default:
            exp_scalar(x, y, n);
    }
}

}  // namespace beamtrace::detail

namespace beamtrace::detail {

void fast_log_lanes(const double* x, double* y, std::size_t n) {
#if BEAMTRACE_EXP_LANES
    if (__builtin_cpu_supports("avx512f")) {
        log_avx512(x, y, n);
    } else if (__builtin_cpu_supports("avx2")) {
        log_avx2(x, y, n);
    } else {
        log_sse2(x, y, n);
    }
#else
    log_scalar(x, y, n);
#endif
}

void fast_log_lanes(ExpLanes path, const double* x, double* y, std::size_t n) {
    switch (path) {
#if BEAMTRACE_EXP_LANES
        case ExpLanes::sse2:
            log_sse2(x, y, n);
            return;
        case ExpLanes::avx2:
            log_avx2(x, y, n);
            return;
        case ExpLanes::avx512:
            log_avx512(x, y, n);
            return;
#endif
        default:
            log_scalar(x, y, n);
    }
}

}  // namespace beamtrace::detail
