#include "physics/detail/gaussian_runs.hpp"

#include <algorithm>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#include <immintrin.h>
#define BEAMTRACE_RUN_LANES 1
#endif

namespace beamtrace::detail {

#if BEAMTRACE_RUN_LANES
namespace {

#define BT_RL __attribute__((target("avx512f"), always_inline)) inline
#define BT_RL_ENTRY __attribute__((target("avx512f")))

using Oct = double __attribute__((vector_size(64)));
using OctIndex = std::int64_t __attribute__((vector_size(64)));

/// v[k] (bin k of eight, lanes the runs) into t[l] (run l, lanes the eight bins).
BT_RL void transpose(const Oct v[8], Oct t[8]) {
    Oct a[8], b[8];
    for (int k = 0; k < 8; k += 2) {
        a[k] = __builtin_shuffle(v[k], v[k + 1], OctIndex{0, 8, 2, 10, 4, 12, 6, 14});
        a[k + 1] = __builtin_shuffle(v[k], v[k + 1], OctIndex{1, 9, 3, 11, 5, 13, 7, 15});
    }
    for (int k = 0; k < 8; k += 4) {
        b[k] = __builtin_shuffle(a[k], a[k + 2], OctIndex{0, 1, 8, 9, 4, 5, 12, 13});
        b[k + 1] = __builtin_shuffle(a[k + 1], a[k + 3], OctIndex{0, 1, 8, 9, 4, 5, 12, 13});
        b[k + 2] = __builtin_shuffle(a[k], a[k + 2], OctIndex{2, 3, 10, 11, 6, 7, 14, 15});
        b[k + 3] = __builtin_shuffle(a[k + 1], a[k + 3], OctIndex{2, 3, 10, 11, 6, 7, 14, 15});
    }
    for (int l = 0; l < 4; ++l) {
        t[l] = __builtin_shuffle(b[l], b[l + 4], OctIndex{0, 1, 2, 3, 8, 9, 10, 11});
        t[l + 4] = __builtin_shuffle(b[l], b[l + 4], OctIndex{4, 5, 6, 7, 12, 13, 14, 15});
    }
}

}  // namespace

bool run_lanes_avx512_available() {
    return __builtin_cpu_supports("avx512f");
}

// The runs in the lanes of one register, all stepping through the same bins: a lane is active
// in its run's bins (its recurrence advances there only) and gives +0 elsewhere. Eight bins of
// eight lanes at a time are transposed so that each run's eight samples add to eight bins.
BT_RL_ENTRY void add_runs_lanes_avx512(double* y, std::size_t width, std::int64_t first,
                                       const GaussianRun* runs, std::size_t count) {
    std::size_t lo = width, hi = 0;  // the bins some run reaches
    for (std::size_t l = 0; l < count; ++l) {
        if (runs[l].n > 0) {
            const auto offset = static_cast<std::size_t>(runs[l].b0 - first);
            lo = std::min(lo, offset);
            hi = std::max(hi, offset + runs[l].n);
        }
    }
    // The runs' fields gathered into lanes (0 beyond count): element loads, which the caller's
    // stores just made forward to (a vector load of scalars stored apart would wait for them).
    static_assert(sizeof(GaussianRun) == 5 * sizeof(double));
    const __m512i field = _mm512_setr_epi64(0, 5, 10, 15, 20, 25, 30, 35);
    const auto used = static_cast<__mmask8>((1u << count) - 1u);
    const __m512d zero = _mm512_setzero_pd();
    __m512d vg = _mm512_mask_i64gather_pd(zero, used, field, &runs->g, 8);
    __m512d vratio = _mm512_mask_i64gather_pd(zero, used, field, &runs->ratio, 8);
    const __m512d vstep = _mm512_mask_i64gather_pd(zero, used, field, &runs->step, 8);
    const __m512i voffset = _mm512_sub_epi64(
        _mm512_mask_i64gather_epi64(_mm512_setzero_si512(), used, field, &runs->b0, 8),
        _mm512_set1_epi64(first));
    const __m512i vn =
        _mm512_mask_i64gather_epi64(_mm512_setzero_si512(), used, field, &runs->n, 8);
    // rel = s - offset, bin s's place in each run, stepped along (active where 0 <= rel < n;
    // unsigned: below 0 wraps past every n).
    __m512i rel = _mm512_sub_epi64(_mm512_set1_epi64(static_cast<std::int64_t>(lo)), voffset);
    const __m512i one = _mm512_set1_epi64(1);
    for (std::size_t s0 = lo; s0 < hi; s0 += 8) {
        Oct v[8], t[8];
        for (std::size_t k = 0; k < 8; ++k) {
            const __mmask8 active = _mm512_cmplt_epu64_mask(rel, vn);
            rel = _mm512_add_epi64(rel, one);
            v[k] = reinterpret_cast<Oct>(_mm512_maskz_mov_pd(active, vg));
            vg = _mm512_mask_mul_pd(vg, active, vg, vratio);
            vratio = _mm512_mask_mul_pd(vratio, active, vratio, vstep);
        }
        transpose(v, t);
        const std::size_t left = std::min<std::size_t>(8, width - s0);
        const auto in = static_cast<__mmask8>((1u << left) - 1u);
        __m512d sum = _mm512_maskz_loadu_pd(in, y + s0);
        for (std::size_t l = 0; l < count; ++l) {
            sum = _mm512_add_pd(sum, reinterpret_cast<__m512d>(t[l]));
        }
        _mm512_mask_storeu_pd(y + s0, in, sum);
    }
}

#else

bool run_lanes_avx512_available() {
    return false;
}

void add_runs_lanes_avx512(double*, std::size_t, std::int64_t, const GaussianRun*, std::size_t) {}

#endif

}  // namespace beamtrace::detail
