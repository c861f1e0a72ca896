#include "physics/detail/gaussian_runs.hpp"

#include <algorithm>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#include <immintrin.h>
#define BEAMTRACE_RUN_LANES_AVX2 1
#endif

namespace beamtrace::detail {

#if BEAMTRACE_RUN_LANES_AVX2
namespace {

#define BT_R4 __attribute__((target("avx2"), always_inline)) inline

/// Four runs in the lanes of AVX2 registers: their recurrences, and rel = s - offset (bin s's
/// place in each run) and n with the sign bit flipped, so that the signed compare n > rel is
/// the unsigned rel < n (active where 0 <= rel < n: below 0 wraps past every n); live: the
/// lanes of a run with bins (all ones), the others 0.
struct Four {
    __m256d g, ratio, step, live;
    __m256i rel, n;
};

/// The runs runs[from, min(from + 4, count)) into lanes (0 beyond count), rel at bin `lo`:
/// gathered element by element, which the caller's stores just made forward to.
BT_R4 Four load_four(const GaussianRun* runs, std::size_t from, std::size_t count,
                     std::int64_t first, std::size_t lo) {
    static_assert(sizeof(GaussianRun) == 5 * sizeof(double));
    const GaussianRun* base = runs + from;
    const __m256i field = _mm256_setr_epi64x(0, 5, 10, 15);
    const auto left = static_cast<long long>(count - from);
    const __m256i used =
        _mm256_cmpgt_epi64(_mm256_set1_epi64x(left), _mm256_setr_epi64x(0, 1, 2, 3));
    const __m256d used_pd = _mm256_castsi256_pd(used);
    const __m256d zero = _mm256_setzero_pd();
    const __m256i zeroi = _mm256_setzero_si256();
    const __m256i sign = _mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ULL));
    const auto* b0 = reinterpret_cast<const long long*>(&base->b0);
    const auto* n = reinterpret_cast<const long long*>(&base->n);
    Four f;
    f.g = _mm256_mask_i64gather_pd(zero, &base->g, field, used_pd, 8);
    f.ratio = _mm256_mask_i64gather_pd(zero, &base->ratio, field, used_pd, 8);
    f.step = _mm256_mask_i64gather_pd(zero, &base->step, field, used_pd, 8);
    const __m256i offset = _mm256_sub_epi64(_mm256_mask_i64gather_epi64(zeroi, b0, field, used, 8),
                                            _mm256_set1_epi64x(first));
    f.rel = _mm256_xor_si256(
        _mm256_sub_epi64(_mm256_set1_epi64x(static_cast<long long>(lo)), offset), sign);
    const __m256i count_n = _mm256_mask_i64gather_epi64(zeroi, n, field, used, 8);
    f.n = _mm256_xor_si256(count_n, sign);
    f.live = _mm256_castsi256_pd(_mm256_andnot_si256(_mm256_cmpeq_epi64(count_n, zeroi), used));
    return f;
}

/// The samples of f's runs at the next four bins, into a[k] (bin k, lanes the runs; +0 where a
/// run is inactive), each lane's recurrence advanced where it is active only.
BT_R4 void step_four(Four& f, __m256d a[4]) {
    const __m256i one = _mm256_set1_epi64x(1);
    for (int k = 0; k < 4; ++k) {
        const __m256d active = _mm256_castsi256_pd(_mm256_cmpgt_epi64(f.n, f.rel));
        f.rel = _mm256_add_epi64(f.rel, one);
        a[k] = _mm256_and_pd(active, f.g);
        f.g = _mm256_blendv_pd(f.g, _mm256_mul_pd(f.g, f.ratio), active);
        f.ratio = _mm256_blendv_pd(f.ratio, _mm256_mul_pd(f.ratio, f.step), active);
    }
}

/// As step_four where every live lane is active at all four bins: the same products, no masks
/// but the live lanes'.
BT_R4 void step_four_live(Four& f, __m256d a[4]) {
    for (int k = 0; k < 4; ++k) {
        a[k] = _mm256_and_pd(f.live, f.g);
        f.g = _mm256_mul_pd(f.g, f.ratio);
        f.ratio = _mm256_mul_pd(f.ratio, f.step);
    }
    f.rel = _mm256_add_epi64(f.rel, _mm256_set1_epi64x(4));
}

/// a[k] (bin k of four, lanes the runs) into t[l] (run l, lanes the four bins).
BT_R4 void transpose(const __m256d a[4], __m256d t[4]) {
    const __m256d t0 = _mm256_unpacklo_pd(a[0], a[1]);
    const __m256d t1 = _mm256_unpackhi_pd(a[0], a[1]);
    const __m256d t2 = _mm256_unpacklo_pd(a[2], a[3]);
    const __m256d t3 = _mm256_unpackhi_pd(a[2], a[3]);
    t[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
    t[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
    t[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
    t[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}

/// The bins [lo, hi) of y (width bins) receive the samples of `groups` fours of runs (count
/// runs in all), four bins at a time, each bin the runs' samples in the order of the runs;
/// every run with bins has all of [inner_lo, inner_hi) (no masks needed there).
template <std::size_t groups, bool full>
BT_R4 void add_fours(double* y, std::size_t width, std::size_t lo, std::size_t hi,
                     std::size_t inner_lo, std::size_t inner_hi, Four* f, std::size_t count) {
    for (std::size_t s0 = lo; s0 < hi; s0 += 4) {
        const bool inner = s0 >= inner_lo && s0 + 4 <= inner_hi;
        // A whole block by plain loads and stores (a masked store is slow on some CPUs: AMD's).
        const bool whole = s0 + 4 <= width;
        const __m256i in = _mm256_cmpgt_epi64(
            _mm256_set1_epi64x(static_cast<long long>(width - s0)), _mm256_setr_epi64x(0, 1, 2, 3));
        __m256d sum = whole ? _mm256_loadu_pd(y + s0) : _mm256_maskload_pd(y + s0, in);
        // Each four's samples join the sum as soon as they are transposed (the runs' order
        // still), so that only four of them are held at once; a full call (count = 4 groups)
        // adds every lane without asking.
        for (std::size_t q = 0; q < groups; ++q) {
            __m256d a[4], t[4];
            if (inner) {
                step_four_live(f[q], a);
            } else {
                step_four(f[q], a);
            }
            transpose(a, t);
            for (std::size_t l = 0; l < 4; ++l) {
                if (full || 4 * q + l < count) {
                    sum = _mm256_add_pd(sum, t[l]);
                }
            }
        }
        if (whole) {
            _mm256_storeu_pd(y + s0, sum);
        } else {
            _mm256_maskstore_pd(y + s0, in, sum);
        }
    }
}

}  // namespace

bool run_lanes_avx2_available() {
    return __builtin_cpu_supports("avx2");
}

// As add_runs_lanes_avx512, with two four-lane registers for the eight runs: a lane is active
// in its run's bins (its recurrence advances there only) and gives +0 elsewhere; four bins of
// four lanes at a time are transposed so that each run's four samples add to four bins. Where
// every run with bins is active at all four bins, the same products go without the masks.
__attribute__((target("avx2"))) void add_runs_lanes_avx2(double* y, std::size_t width,
                                                         std::int64_t first,
                                                         const GaussianRun* runs,
                                                         std::size_t count) {
    std::size_t lo = width, hi = 0;              // the bins some run reaches
    std::size_t inner_lo = 0, inner_hi = width;  // the bins every run with bins reaches
    for (std::size_t l = 0; l < count; ++l) {
        if (runs[l].n > 0) {
            const auto offset = static_cast<std::size_t>(runs[l].b0 - first);
            lo = std::min(lo, offset);
            hi = std::max(hi, offset + runs[l].n);
            inner_lo = std::max(inner_lo, offset);
            inner_hi = std::min(inner_hi, offset + runs[l].n);
        }
    }
    if (lo >= hi) {
        return;
    }
    Four f[2];
    f[0] = load_four(runs, 0, count, first, lo);
    if (count <= 4) {
        if (count == 4) {
            add_fours<1, true>(y, width, lo, hi, inner_lo, inner_hi, f, count);
        } else {
            add_fours<1, false>(y, width, lo, hi, inner_lo, inner_hi, f, count);
        }
        return;
    }
    f[1] = load_four(runs, 4, count, first, lo);
    if (count == 8) {
        add_fours<2, true>(y, width, lo, hi, inner_lo, inner_hi, f, count);
    } else {
        add_fours<2, false>(y, width, lo, hi, inner_lo, inner_hi, f, count);
    }
}

#else

bool run_lanes_avx2_available() {
    return false;
}

void add_runs_lanes_avx2(double*, std::size_t, std::int64_t, const GaussianRun*, std::size_t) {}

#endif

}  // namespace beamtrace::detail
