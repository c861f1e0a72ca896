#include "physics/detail/gaussian_runs.hpp"

#include <algorithm>
#include <array>
#include <utility>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#include <immintrin.h>
#define BEAMTRACE_RUN_LANES_AVX2 1
#endif

namespace beamtrace::detail {

#if BEAMTRACE_RUN_LANES_AVX2
namespace {

#define BT_R4 __attribute__((target("avx2"), always_inline)) inline

/// Four runs in the lanes of AVX2 registers: their recurrences (all 0 in the lanes of a run
/// without bins and beyond the runs, so that their samples are +0 without a mask), and rel0 =
/// lo - offset (bin lo's place in each run) and n with the sign bit flipped, so that the signed
/// compare n > rel is the unsigned rel < n (active where 0 <= rel < n: below 0 wraps past every
/// n; flipping the sign bit commutes with adding to rel).
struct Four {
    __m256d g, ratio, step;
    __m256i rel0, n;
};

/// The runs runs[from, min(from + 4, count)) into lanes, rel0 at bin `lo`: gathered element by
/// element, which the caller's stores just made forward to.
BT_R4 Four load_four(const GaussianRun* runs, std::size_t from, std::size_t count,
                     std::int64_t first, std::size_t lo) {
    static_assert(sizeof(GaussianRun) == 5 * sizeof(double));
    const GaussianRun* base = runs + from;
    const __m256i field = _mm256_setr_epi64x(0, 5, 10, 15);
    const auto left = static_cast<long long>(count - from);
    const __m256i used =
        _mm256_cmpgt_epi64(_mm256_set1_epi64x(left), _mm256_setr_epi64x(0, 1, 2, 3));
    const __m256d zero = _mm256_setzero_pd();
    const __m256i zeroi = _mm256_setzero_si256();
    const __m256i sign = _mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ULL));
    const auto* b0 = reinterpret_cast<const long long*>(&base->b0);
    const auto* n = reinterpret_cast<const long long*>(&base->n);
    const __m256i count_n = _mm256_mask_i64gather_epi64(zeroi, n, field, used, 8);
    const __m256d live =
        _mm256_castsi256_pd(_mm256_andnot_si256(_mm256_cmpeq_epi64(count_n, zeroi), used));
    Four f;
    f.g = _mm256_mask_i64gather_pd(zero, &base->g, field, live, 8);
    f.ratio = _mm256_mask_i64gather_pd(zero, &base->ratio, field, live, 8);
    f.step = _mm256_mask_i64gather_pd(zero, &base->step, field, live, 8);
    const __m256i offset = _mm256_sub_epi64(_mm256_mask_i64gather_epi64(zeroi, b0, field, used, 8),
                                            _mm256_set1_epi64x(first));
    f.rel0 = _mm256_xor_si256(
        _mm256_sub_epi64(_mm256_set1_epi64x(static_cast<long long>(lo)), offset), sign);
    f.n = _mm256_xor_si256(count_n, sign);
    return f;
}

/// The samples of f's runs at the four bins from rel (each run's place), into a[k] (bin k, lanes
/// the runs; +0 where a run is inactive), each lane's recurrence advanced where it is active.
BT_R4 void step_four(Four& f, __m256i rel, __m256d a[4]) {
    const __m256i one = _mm256_set1_epi64x(1);
    for (int k = 0; k < 4; ++k) {
        const __m256d active = _mm256_castsi256_pd(_mm256_cmpgt_epi64(f.n, rel));
        rel = _mm256_add_epi64(rel, one);
        a[k] = _mm256_and_pd(active, f.g);
        f.g = _mm256_blendv_pd(f.g, _mm256_mul_pd(f.g, f.ratio), active);
        f.ratio = _mm256_blendv_pd(f.ratio, _mm256_mul_pd(f.ratio, f.step), active);
    }
}

/// As step_four where every run with bins is active at all four bins: the same products, no
/// masks (the other lanes' recurrences are 0 and stay +0).
BT_R4 void step_four_live(Four& f, __m256d a[4]) {
    for (int k = 0; k < 4; ++k) {
        a[k] = f.g;
        f.g = _mm256_mul_pd(f.g, f.ratio);
        f.ratio = _mm256_mul_pd(f.ratio, f.step);
    }
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

/// sum plus the samples of `groups` fours of runs at four bins (the last four holding `last`
/// runs), each bin the runs' samples in the order of the runs; inner: every run with bins is
/// active at all four (else rel: bin s0 - lo, where the block starts, as each run's rel0).
template <std::size_t groups, std::size_t last, bool inner>
BT_R4 __m256d add_block(__m256d sum, Four* f, __m256i rel) {
    // Each four's samples join the sum as soon as they are transposed (the runs' order still),
    // so that only four of them are held at once.
    for (std::size_t q = 0; q < groups; ++q) {
        __m256d a[4], t[4];
        if constexpr (inner) {
            step_four_live(f[q], a);
        } else {
            step_four(f[q], _mm256_add_epi64(f[q].rel0, rel), a);
        }
        transpose(a, t);
        const std::size_t lanes = q + 1 == groups ? last : 4;
        for (std::size_t l = 0; l < lanes; ++l) {
            sum = _mm256_add_pd(sum, t[l]);
        }
    }
    return sum;
}

/// One block of add_fours from bin s0 by masks; a whole block by plain loads and stores (a
/// masked store is slow on some CPUs: AMD's), the last by masked ones where it passes the width.
template <std::size_t groups, std::size_t last>
BT_R4 void add_masked(double* y, std::size_t width, std::size_t s0, std::size_t lo, Four* f) {
    const __m256i rel = _mm256_set1_epi64x(static_cast<long long>(s0 - lo));
    if (s0 + 4 <= width) {
        _mm256_storeu_pd(y + s0, add_block<groups, last, false>(_mm256_loadu_pd(y + s0), f, rel));
        return;
    }
    const __m256i in = _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<long long>(width - s0)),
                                          _mm256_setr_epi64x(0, 1, 2, 3));
    _mm256_maskstore_pd(y + s0, in,
                        add_block<groups, last, false>(_mm256_maskload_pd(y + s0, in), f, rel));
}

/// The bins [lo, hi) of y (width bins) receive the samples of `groups` fours of runs (the last
/// holding `last` runs), four bins at a time: by masks before and after the blocks inside
/// [inner_lo, inner_hi), which every run with bins reaches (no masks there).
template <std::size_t groups, std::size_t last>
__attribute__((target("avx2"))) void add_fours(double* y, std::size_t width, std::size_t lo,
                                               std::size_t hi, std::size_t inner_lo,
                                               std::size_t inner_hi, Four* f) {
    // The inner blocks [live_from, live_to): those from lo, four bins each, inside the inner bins.
    std::size_t live_from = lo, live_to = lo;
    if (inner_hi >= inner_lo + 4) {
        live_from = lo + (inner_lo - lo + 3) / 4 * 4;
        live_to = inner_hi >= live_from ? live_from + (inner_hi - live_from) / 4 * 4 : live_from;
    }
    std::size_t s0 = lo;
    for (; s0 < live_from; s0 += 4) {
        add_masked<groups, last>(y, width, s0, lo, f);
    }
    for (; s0 < live_to; s0 += 4) {  // whole blocks: inner_hi <= width
        _mm256_storeu_pd(y + s0, add_block<groups, last, true>(_mm256_loadu_pd(y + s0), f,
                                                               _mm256_setzero_si256()));
    }
    for (; s0 < hi; s0 += 4) {
        add_masked<groups, last>(y, width, s0, lo, f);
    }
}

/// Runs added in one pass over the bins by add_fours, at most: five fours (sixteen registers
/// cannot hold more than a few fours' recurrences; the others wait in memory).
constexpr std::size_t kPassRuns = 20;

using PassFn = void (*)(double*, std::size_t, std::size_t, std::size_t, std::size_t, std::size_t,
                        Four*);

/// add_fours for `count` runs (1 <= count <= kPassRuns) at passes[count - 1].
template <std::size_t... i>
constexpr std::array<PassFn, sizeof...(i)> pass_table(std::index_sequence<i...>) {
    return {&add_fours<(i + 4) / 4, i % 4 + 1>...};
}
constexpr auto kPasses = pass_table(std::make_index_sequence<kPassRuns>{});

/// Adds runs[0, count) (1 <= count <= kPassRuns) in one pass over the bins they reach.
__attribute__((target("avx2"))) void add_pass(double* y, std::size_t width, std::int64_t first,
                                              const GaussianRun* runs, std::size_t count) {
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
    Four f[kPassRuns / 4];
    for (std::size_t q = 0; 4 * q < count; ++q) {
        f[q] = load_four(runs, 4 * q, count, first, lo);
    }
    kPasses[count - 1](y, width, lo, hi, inner_lo, inner_hi, f);
}

}  // namespace

bool run_lanes_avx2_available() {
    return __builtin_cpu_supports("avx2");
}

// As add_runs_lanes_avx512, with up to five four-lane registers for up to twenty runs a pass
// over the bins: a lane is active in its run's bins (its recurrence advances there only) and
// gives +0 elsewhere; four bins of four lanes at a time are transposed so that each run's four
// samples add to four bins. Where every run with bins is active at all four bins, the same
// products go without the masks.
__attribute__((target("avx2"))) void add_runs_lanes_avx2(double* y, std::size_t width,
                                                         std::int64_t first,
                                                         const GaussianRun* runs,
                                                         std::size_t count) {
    for (std::size_t from = 0; from < count; from += kPassRuns) {
        add_pass(y, width, first, runs + from, std::min(kPassRuns, count - from));
    }
}

#else

bool run_lanes_avx2_available() {
    return false;
}

void add_runs_lanes_avx2(double*, std::size_t, std::int64_t, const GaussianRun*, std::size_t) {}

#endif

}  // namespace beamtrace::detail
