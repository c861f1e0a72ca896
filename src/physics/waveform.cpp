#include "beamtrace/physics/waveform.hpp"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>

#include "physics/detail/fast_exp.hpp"
#include "physics/detail/fast_log.hpp"
#include "physics/detail/gaussian_runs.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace beamtrace {
namespace {

/// FWHM / sigma of a Gaussian.
const double kFwhmPerSigma = 2.0 * std::sqrt(2.0 * std::log(2.0));
const double kSqrtTwoPi = std::sqrt(2.0 * std::numbers::pi);

using detail::GaussianRun;

/// The exponents of the run from bin b0 of width h [ns] of amplitude * exp(-(t - t0)^2 /
/// (2 sigma^2)), inv_two_var = 1 / (2 sigma^2): their exps are its first sample over the
/// amplitude, its first ratio and the ratio's step (GaussianRun), at e[0], e[stride] and
/// e[2 stride].
void run_exponents(double h, std::int64_t b0, double t0, double inv_two_var, double* e,
                   std::size_t stride) {
    const double dt0 = static_cast<double>(b0) * h - t0;
    e[0] = -dt0 * dt0 * inv_two_var;
    e[stride] = -(2.0 * dt0 * h + h * h) * inv_two_var;
    e[2 * stride] = -2.0 * h * h * inv_two_var;
}

/// static_cast<std::int64_t>(std::floor(x)) and (ceil) without the libm calls (baseline x86-64
/// has no rounding instruction): the truncation, one step down (up) where it passed x. The
/// same integer for every x whose floor fits, and 0x8000000000000000 (x86's conversion of NaN
/// and of what does not fit) where the truncation gives it.
std::int64_t floor_to_int(double x) {
    constexpr std::int64_t kIndefinite = std::numeric_limits<std::int64_t>::min();
    const auto i = static_cast<std::int64_t>(x);
    return i != kIndefinite && static_cast<double>(i) > x ? i - 1 : i;
}
std::int64_t ceil_to_int(double x) {
    constexpr std::int64_t kIndefinite = std::numeric_limits<std::int64_t>::min();
    const auto i = static_cast<std::int64_t>(x);
    return i != kIndefinite && static_cast<double>(i) < x ? i + 1 : i;
}

/// Runs sampled and added together: kRows of them, each row of the waveform's width.
constexpr std::size_t kRows = detail::kRunLanes;
/// Up to this many runs are added one after the other (each bin receives them in the same
/// order as from the rows): cheaper than the lanes for a single ray's pulse.
constexpr std::size_t kRunsOneByOne = 2;

// The loops below are compiled for AVX2 too (4 doubles a step), chosen at run time: the
// same products and sums, IEEE-rounded alike (no FMA: AVX2 does not imply it). Not under
// ThreadSanitizer: the clones' ifunc resolver runs while the program is relocated, before the
// TSan runtime is up, and its instrumented code crashes there.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_THREAD__)
#define BEAMTRACE_WAVEFORM_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define BEAMTRACE_WAVEFORM_CLONES
#endif

/// Contributions whose runs are made together (their exps in one pass), then added together
/// (kRows at a time before AVX2).
constexpr std::size_t kBatch = detail::kRunsPerCall;
static_assert(kBatch % kRows == 0);

/// The divisions of up to kBatch runs, each rounded as alone (the AVX2 clone: four at a time):
/// of the run at round-trip time t[i] of width sigma[i], its reach's ends in bins (lo, hi,
/// before floor and ceil), 1 / (2 sigma^2) and sigma_p / sigma; and each one's peak power and
/// whether it is stretched (EchoContribution).
struct RunQuotients {
    double t[kBatch], sigma[kBatch];
    double lo[kBatch], hi[kBatch], inv_two_var[kBatch], shrink[kBatch];
    double amplitude[kBatch];
    bool stretched[kBatch];
};

BEAMTRACE_WAVEFORM_CLONES void run_quotients(RunQuotients& q, std::size_t n, double bin_ns,
                                             double sigma_p) {
    for (std::size_t i = 0; i < n; ++i) {
        const double reach_ns = 5.0 * q.sigma[i];
        q.lo[i] = (q.t[i] - reach_ns) / bin_ns;
        q.hi[i] = (q.t[i] + reach_ns) / bin_ns;
        q.inv_two_var[i] = 1.0 / (2.0 * q.sigma[i] * q.sigma[i]);
        q.shrink[i] = sigma_p / q.sigma[i];
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
/// make_runs' bins and exponents of runs [0, count) four at a time (AVX2, no FMA: each product
/// and sum rounded alone, run_exponents' order), for the fours whose reach ends lie within
/// 2^52 bins: there floor and ceil are exact in doubles and equal floor_to_int's and
/// ceil_to_int's integers (+0 for 0, as the integer's conversion gives). Each run's b0 and n
/// into runs[i], its exponents into e[i], e[count + i], e[2 count + i]. The last four end at
/// count (they overlap the four before them: each lane's result alone, the same again). Returns
/// how many it did: the runs before the first four it leaves, or count (0 where count < 4).
__attribute__((target("avx2"))) std::size_t run_bins_avx2(const RunQuotients& q, std::size_t count,
                                                          double h, std::int64_t first,
                                                          std::int64_t last, GaussianRun* runs,
                                                          double* e) {
    const __m256d big = _mm256_set1_pd(0x1p52), zero = _mm256_setzero_pd();
    const __m256d sign = _mm256_set1_pd(-0.0), hv = _mm256_set1_pd(h);
    const __m256d first_d = _mm256_set1_pd(static_cast<double>(first));
    const __m256d last_d = _mm256_set1_pd(static_cast<double>(last));
    const __m256d hh = _mm256_mul_pd(hv, hv);
    const __m256d two_hh = _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(-2.0), hv), hv);
    if (!(std::abs(static_cast<double>(first)) < 0x1p52) ||
        !(std::abs(static_cast<double>(last)) < 0x1p52)) {
        return 0;
    }
    for (std::size_t next = 0; next < count && count >= 4; next += 4) {
        const std::size_t i = std::min(next, count - 4);
        const __m256d lo = _mm256_loadu_pd(q.lo + i), hi = _mm256_loadu_pd(q.hi + i);
        const __m256d near =
            _mm256_and_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, lo), big, _CMP_LT_OQ),
                          _mm256_cmp_pd(_mm256_andnot_pd(sign, hi), big, _CMP_LT_OQ));
        if (_mm256_movemask_pd(near) != 0xf) {
            return i;
        }
        const __m256d b0 = _mm256_add_pd(_mm256_max_pd(_mm256_floor_pd(lo), first_d), zero);
        const __m256d b1 = _mm256_min_pd(_mm256_ceil_pd(hi), last_d);
        const __m256d some = _mm256_cmp_pd(b1, b0, _CMP_GE_OQ);
        const __m256d inv = _mm256_loadu_pd(q.inv_two_var + i);
        const __m256d dt0 = _mm256_sub_pd(_mm256_mul_pd(b0, hv), _mm256_loadu_pd(q.t + i));
        const __m256d e0 = _mm256_mul_pd(_mm256_mul_pd(_mm256_xor_pd(dt0, sign), dt0), inv);
        const __m256d e1 = _mm256_mul_pd(
            _mm256_xor_pd(
                _mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(2.0), dt0), hv), hh),
                sign),
            inv);
        _mm256_storeu_pd(e + i, _mm256_and_pd(some, e0));
        _mm256_storeu_pd(e + count + i, _mm256_and_pd(some, e1));
        _mm256_storeu_pd(e + 2 * count + i, _mm256_and_pd(some, _mm256_mul_pd(two_hh, inv)));
        alignas(32) double b0s[4], b1s[4];
        _mm256_store_pd(b0s, b0);
        _mm256_store_pd(b1s, b1);
        for (std::size_t l = 0; l < 4; ++l) {
            runs[i + l] = GaussianRun{};
            runs[i + l].b0 = static_cast<std::int64_t>(b0s[l]);
            if (b1s[l] >= b0s[l]) {
                runs[i + l].n = static_cast<std::size_t>(b1s[l] - b0s[l]) + 1;
            }
        }
    }
    return count >= 4 ? count : 0;
}
#endif

/// The runs of q's `count` contributions, each inside the bins [first, last] (width h [ns]):
/// their 3 count exps in one pass of fast_exp_lanes (the same bits in every lane and path).
void make_runs(RunQuotients& q, std::size_t count, double h, double sigma_p, std::int64_t first,
               std::int64_t last, GaussianRun* runs) {
    run_quotients(q, count, h, sigma_p);
    double e[3 * kBatch];
    std::size_t i = 0;
#if defined(__x86_64__) && defined(__GNUC__)
    if (__builtin_cpu_supports("avx2")) {
        i = run_bins_avx2(q, count, h, first, last, runs, e);
    }
#endif
    for (; i < count; ++i) {
        const std::int64_t b0 = std::max(first, floor_to_int(q.lo[i]));
        const std::int64_t b1 = std::min(last, ceil_to_int(q.hi[i]));
        runs[i] = GaussianRun{};
        runs[i].b0 = b0;
        if (b1 >= b0) {
            runs[i].n = static_cast<std::size_t>(b1 - b0 + 1);
            run_exponents(h, b0, q.t[i], q.inv_two_var[i], e + i, count);
        } else {
            for (std::size_t k = 0; k < 3; ++k) {
                e[i + k * count] = 0.0;  // an empty run: no exps needed
            }
        }
    }
    detail::fast_exp_lanes(e, e, 3 * count);
    for (std::size_t j = 0; j < count; ++j) {
        if (runs[j].n > 0) {
            // The stretched echo keeps its energy: its peak drops as sigma_p / sigma.
            const double a = q.amplitude[j];
            runs[j].g = (q.stretched[j] ? a * q.shrink[j] : a) * e[j];
            runs[j].ratio = e[count + j];
            runs[j].step = e[2 * count + j];
        }
    }
}

/// Four doubles (two SSE2 registers by default, one AVX2 register in its clone).
using Quad = double __attribute__((vector_size(32)));
using QuadIndex = std::int64_t __attribute__((vector_size(32)));

/// The recurrences of up to kRows runs, four to a Quad (unused lanes 0), and where each run's
/// first bin lies in its row.
struct RunLanes {
    Quad g[2] = {}, ratio[2] = {}, step[2] = {};
    double* at[kRows] = {};
};

/// The lanes of runs[0, count) over rows[l * width, (l + 1) * width) (the waveform's bins from
/// `first`, each run inside them): +0 in the bins a run does not reach; the rows of the unused
/// lanes are written from their start.
RunLanes start_lanes(const GaussianRun* runs, std::size_t count, std::int64_t first, double* rows,
                     std::size_t width) {
    RunLanes r;
    for (std::size_t l = 0; l < kRows; ++l) {
        r.at[l] = rows + l * width;
    }
    for (std::size_t l = 0; l < count; ++l) {
        r.g[l / 4][l % 4] = runs[l].g;
        r.ratio[l / 4][l % 4] = runs[l].ratio;
        r.step[l / 4][l % 4] = runs[l].step;
        // b0 >= first, and b0 + n - 1 <= the last bin when n > 0 (build_waveform clamps them).
        const auto offset = std::min(static_cast<std::size_t>(runs[l].b0 - first), width);
        std::fill(r.at[l], r.at[l] + offset, 0.0);
        std::fill(r.at[l] + std::min(offset + runs[l].n, width), r.at[l] + width, 0.0);
        r.at[l] += offset;
    }
    return r;
}

/// The samples of runs[0, count) (count <= kRows) into their rows (start_lanes): each lane's
/// products in the order of its run alone, so each sample rounds as it did alone. Four bins of
/// four runs at a time are transposed so that each run's four samples are stored at once.
/// (Before AVX2 only: add_runs_lanes adds the runs on CPUs with AVX2 or AVX-512.)
void sample_runs(const GaussianRun* runs, std::size_t count, std::int64_t first, double* rows,
                 std::size_t width) {
    RunLanes r = start_lanes(runs, count, first, rows, width);
    std::size_t common = count == 0 ? 0 : runs[0].n;  // at most width
    for (std::size_t l = 1; l < count; ++l) {
        common = std::min(common, runs[l].n);
    }
    const std::size_t groups = (count + 3) / 4;
    std::size_t s = 0;
    for (; s + 4 <= common; s += 4) {
        for (std::size_t q = 0; q < groups; ++q) {
            Quad a[4];
            for (Quad& v : a) {
                v = r.g[q];
                r.g[q] *= r.ratio[q];
                r.ratio[q] *= r.step[q];
            }
            const Quad t0 = __builtin_shuffle(a[0], a[1], QuadIndex{0, 4, 2, 6});
            const Quad t1 = __builtin_shuffle(a[0], a[1], QuadIndex{1, 5, 3, 7});
            const Quad t2 = __builtin_shuffle(a[2], a[3], QuadIndex{0, 4, 2, 6});
            const Quad t3 = __builtin_shuffle(a[2], a[3], QuadIndex{1, 5, 3, 7});
            const Quad lane[4] = {__builtin_shuffle(t0, t2, QuadIndex{0, 1, 4, 5}),
                                  __builtin_shuffle(t1, t3, QuadIndex{0, 1, 4, 5}),
                                  __builtin_shuffle(t0, t2, QuadIndex{2, 3, 6, 7}),
                                  __builtin_shuffle(t1, t3, QuadIndex{2, 3, 6, 7})};
            for (std::size_t l = 0; l < 4; ++l) {
                std::memcpy(r.at[4 * q + l] + s, &lane[l], sizeof(Quad));
            }
        }
    }
    for (std::size_t l = 0; l < count; ++l) {  // the last bins, one run at a time
        double g = r.g[l / 4][l % 4], ratio = r.ratio[l / 4][l % 4];
        const double step = r.step[l / 4][l % 4];
        for (std::size_t b = s; b < runs[l].n; ++b) {
            r.at[l][b] = g;
            g *= ratio;
            ratio *= step;
        }
    }
}

/// y[s] = (((y[s] + rows[0][s]) + rows[1][s]) + ...) for the `count` rows of `width` bins.
void add_rows(double* y, const double* rows, std::size_t count, std::size_t width) {
    std::size_t s = 0;
    for (; s + 4 <= width; s += 4) {
        Quad v;
        std::memcpy(&v, y + s, sizeof v);
        for (std::size_t l = 0; l < count; ++l) {
            Quad r;
            std::memcpy(&r, rows + l * width + s, sizeof r);
            v += r;
        }
        std::memcpy(y + s, &v, sizeof v);
    }
    for (; s < width; ++s) {
        double v = y[s];
        for (std::size_t l = 0; l < count; ++l) {
            v += rows[l * width + s];
        }
        y[s] = v;
    }
}

/// Adds runs[0, count) (count <= kBatch) to `out`, in order: every bin receives their samples
/// in the order of the runs, as one run after the other would add them. A run adds +0 to the
/// bins it does not reach, which leaves them as they are: a bin is never -0 (it starts at +0,
/// and a sum is -0 only when both terms are).
void add_runs(Waveform& out, const GaussianRun* runs, std::size_t count) {
    thread_local std::vector<double> rows;  // grows once per thread: no allocation per pulse
    if (count == 0) {
        return;
    }
    const std::size_t width = out.samples_w.size();
    if (count <= kRunsOneByOne) {  // a single ray's pulse: its run alone, straight into the bins
        for (std::size_t l = 0; l < count; ++l) {
            double* y = out.samples_w.data() + (runs[l].b0 - out.first_bin);
            double g = runs[l].g, ratio = runs[l].ratio;
            for (std::size_t b = 0; b < runs[l].n; ++b) {
                y[b] += g;
                g *= ratio;
                ratio *= runs[l].step;
            }
        }
        return;
    }
    if (detail::run_lanes_available()) {  // AVX2 or AVX-512: the runs in lanes, no rows
        detail::add_runs_lanes(out.samples_w.data(), width, out.first_bin, runs, count);
        return;
    }
    if (rows.size() < kRows * width) {
        rows.resize(kRows * width);
    }
    for (std::size_t c0 = 0; c0 < count; c0 += kRows) {
        const std::size_t rows_used = std::min(kRows, count - c0);
        sample_runs(runs + c0, rows_used, out.first_bin, rows.data(), width);
        add_rows(out.samples_w.data(), rows.data(), rows_used, width);
    }
}

/// A fitted Gaussian: centre (absolute round-trip time) [ns], amplitude [W], sigma [ns].
struct GaussianFit {
    double centre_ns = 0.0;
    double amplitude = 0.0;
    double sigma_ns = 0.0;

    /// exp(-0.5 d^2) is exactly 0 in doubles beyond 38.6 sigma: at() skips the call there.
    static constexpr double kUnderflow = 38.7;

    [[nodiscard]] double at(double t_ns) const {
        const double d = (t_ns - centre_ns) / sigma_ns;
        return std::abs(d) > kUnderflow ? 0.0 : amplitude * std::exp(-0.5 * d * d);
    }
    /// True when at() is exactly 0 at every time of [lo_ns, hi_ns] (d grows with t, so both
    /// ends beyond kUnderflow on one side); false for a NaN (at() is NaN there too).
    [[nodiscard]] bool zero_on(double lo_ns, double hi_ns) const {
        return (lo_ns - centre_ns) / sigma_ns > kUnderflow ||
               (hi_ns - centre_ns) / sigma_ns < -kUnderflow;
    }
};

/// The samples [lo, hi] of one echo; top is its highest sample.
struct EchoSpan {
    std::size_t lo = 0, hi = 0, top = 0;
};

/// The samples [lo, hi] whose values a fit kept (lo > hi: it kept none).
struct FitSamples {
    std::size_t lo = 1, hi = 0;
};

/// Subtracting x >= 0 leaves v > 0 unchanged when x < v 2^-54 (below half an ulp, also for a
/// power of 2). The bound below asks x < v 2^-55 e^-1: room for exp's and log's last bits.
const double kNegligibleLog = 55.0 * std::numbers::ln2 + 1.0;
/// ln(amplitude / floor) is below this for every ratio under 2^64; beyond this d^2 / 2 no log
/// is needed to see the bound met.
const double kNegligibleNoLog = 64.0 * std::numbers::ln2 + kNegligibleLog;

/// The binary exponent of a finite x > 0: x < 2^(exponent + 1) (also for a subnormal).
int exponent_of(double x) {
    return static_cast<int>((std::bit_cast<std::uint64_t>(x) >> 52) & 0x7ff) - 1023;
}

/// True when |f.at(t)| < floor_w 2^-55 e^-1 at every time of [lo_ns, hi_ns] (floor_w > 0), so
/// that subtracting it from a value of at least floor_w leaves that value as it is; false for a
/// fit with a NaN. |d| grows away from the centre (rounding is monotonic), so the nearer end
/// bounds every at() of the interval.
bool negligible_on(const GaussianFit& f, double lo_ns, double hi_ns, double floor_w) {
    double d = (lo_ns - f.centre_ns) / f.sigma_ns;
    if (!(d > 0)) {
        d = (f.centre_ns - hi_ns) / f.sigma_ns;
        if (!(d > 0)) {
            return false;
        }
    }
    if (d > GaussianFit::kUnderflow) {
        return true;  // at() is exactly 0 there
    }
    const double half_d2 = 0.5 * d * d, amplitude = std::abs(f.amplitude);
    if (half_d2 > kNegligibleNoLog && amplitude < floor_w * 0x1p64) {
        return true;
    }
    // Without the log where the answer shows: a near neighbour at least as high as the floor
    // (the log is at least ln 1 = 0), or a far one whose exponents bound the log
    // (amplitude / floor_w < 2^octaves).
    if (!(half_d2 > kNegligibleLog) && amplitude >= floor_w) {
        return false;
    }
    if (amplitude > 0 && std::isfinite(amplitude) &&
        floor_w >= std::numeric_limits<double>::min()) {
        const int octaves = exponent_of(amplitude) - exponent_of(floor_w) + 1;
        if (half_d2 > static_cast<double>(octaves) * std::numbers::ln2 + kNegligibleLog) {
            return true;
        }
    }
    return half_d2 > std::log(amplitude / floor_w) + kNegligibleLog;
}

/// v - f.at(t_ns), bit for bit, without the exp where f.at(t_ns) is 0 or provably below half
/// an ulp of v: v a positive normal number and |f.at(t_ns)| < v 2^-55 e^-1 (|amplitude| below
/// 2^(its exponent + 1), v at least 2^(its exponent)).
double minus_fit(double v, const GaussianFit& f, double t_ns) {
    const double d = (t_ns - f.centre_ns) / f.sigma_ns;  // as at() computes it
    if (std::abs(d) > GaussianFit::kUnderflow) {
        return v;  // at() is exactly 0
    }
    if (v >= std::numeric_limits<double>::min() && std::abs(f.amplitude) > 0 &&
        std::isfinite(f.amplitude)) {
        const int octaves = exponent_of(std::abs(f.amplitude)) - exponent_of(v) + 1;
        if (0.5 * d * d > static_cast<double>(octaves) * std::numbers::ln2 + kNegligibleLog) {
            return v;
        }
    }
    return v - f.amplitude * std::exp(-0.5 * d * d);
}

/// The weighted least-squares Gaussian (Caruana's parabola through ln v, Guo's weights v^2) over
/// the samples v(m) of the span, contiguous around its top, of at least kEchoFitFraction of
/// v(top); false when fewer than 3 samples or no downward parabola (the caller falls back).
/// Working space of the fits: the values of one fit's samples.
struct FitScratch {
    std::vector<double> left, right;
    std::vector<double> logs;       ///< ln(v / peak) of the kept samples, from the first
    std::vector<std::size_t> near;  ///< the other fits not 0 on the span being fitted
};

template <typename Value>
bool fit_gaussian(const Waveform& waveform, const EchoSpan& span, Value v, FitScratch& scratch,
                  GaussianFit& fit, FitSamples& kept) {
    kept = {};
    const double peak = v(span.top);
    const double floor_w = kEchoFitFraction * peak;
    if (!(peak > 0)) {
        return false;
    }
    // Each sample's value once (v may be a residual, costly): those left of the top, nearest
    // first, then the top and those right of it.
    std::vector<double>& left = scratch.left;
    std::vector<double>& right = scratch.right;
    left.clear();
    right.assign(1, peak);
    std::size_t a = span.top, b = span.top;
    for (double x = 0; a > span.lo && (x = v(a - 1)) >= floor_w; --a) {
        left.push_back(x);
    }
    for (double x = 0; b < span.hi && (x = v(b + 1)) >= floor_w; ++b) {
        right.push_back(x);
    }
    kept = {a, b};
    if (b - a < 2) {
        return false;
    }
    const auto value = [&](std::size_t m) {
        return m < span.top ? left[span.top - m - 1] : right[m - span.top];
    };
    // The logs of the samples over the peak in one pass of fast_log_lanes (ln 1 is exactly 0).
    std::vector<double>& logs = scratch.logs;
    logs.resize(b - a + 1);
    for (std::size_t m = a; m < span.top; ++m) {  // the two sides apart: loops that vectorise
        logs[m - a] = left[span.top - m - 1] / peak;
    }
    for (std::size_t m = span.top; m <= b; ++m) {
        logs[m - a] = right[m - span.top] / peak;
    }
    detail::fast_log_lanes(logs.data(), logs.data(), logs.size());
    // Moments in bins from the top: s[n] = sum w t^n, r[n] = sum w ln(v / peak) t^n, w = v^2.
    double s[5] = {0, 0, 0, 0, 0}, r[3] = {0, 0, 0};
    for (std::size_t m = a; m <= b; ++m) {
        const double t = static_cast<double>(m) - static_cast<double>(span.top);
        const double y = value(m), l = logs[m - a];
        double tn = y * y;
        for (int n = 0; n < 5; ++n) {
            s[n] += tn;
            if (n < 3) {
                r[n] += tn * l;
            }
            tn *= t;
        }
    }
    // Cramer's rule on [[s0 s1 s2] [s1 s2 s3] [s2 s3 s4]] (c0 c1 c2) = (r0 r1 r2).
    const auto det3 = [](double a11, double a12, double a13, double a21, double a22, double a23,
                         double a31, double a32, double a33) {
        return a11 * (a22 * a33 - a23 * a32) - a12 * (a21 * a33 - a23 * a31) +
               a13 * (a21 * a32 - a22 * a31);
    };
    const double det = det3(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);
    const double c0 = det3(r[0], s[1], s[2], r[1], s[2], s[3], r[2], s[3], s[4]) / det;
    const double c1 = det3(s[0], r[0], s[2], s[1], r[1], s[3], s[2], r[2], s[4]) / det;
    const double c2 = det3(s[0], s[1], r[0], s[1], s[2], r[1], s[2], s[3], r[2]) / det;
    const double vertex = -c1 / (2.0 * c2);  // bins from the top
    if (!(c2 < 0) || !std::isfinite(c0) ||
        !(vertex >= static_cast<double>(a) - static_cast<double>(span.top)) ||
        !(vertex <= static_cast<double>(b) - static_cast<double>(span.top))) {
        return false;
    }
    const double h = waveform.bin_ns;
    fit.centre_ns = waveform.time_ns(span.top) + vertex * h;
    fit.sigma_ns = h / std::sqrt(-2.0 * c2);
    fit.amplitude = peak * std::exp(c0 - c1 * c1 / (4.0 * c2));
    return true;
}

/// True when subtracting the other fits leaves every sample that the first fit of span e kept
/// (`kept`, each of at least kEchoFitFraction of its top) as it is: the refit then reads the same
/// values, keeps the same samples, and is the first fit again, bit for bit. (The samples where
/// the first fit stopped stay below its floor: the fits are not negative.)
bool others_negligible(const Waveform& waveform, const EchoSpan& span,
                       const std::vector<GaussianFit>& others, std::size_t e,
                       const FitSamples& kept) {
    const double floor_w = kEchoFitFraction * waveform.samples_w[span.top];
    if (kept.lo > kept.hi || !(floor_w > 0)) {
        return false;
    }
    const double lo_ns = waveform.time_ns(kept.lo), hi_ns = waveform.time_ns(kept.hi);
    for (std::size_t o = 0; o < others.size(); ++o) {
        if (o != e && !negligible_on(others[o], lo_ns, hi_ns, floor_w)) {
            return false;
        }
    }
    return true;
}

/// The fit of `span` on the samples less the fitted Gaussians of the other echoes (none given:
/// the samples themselves), or the top sample with the pulse's width when it fails. `others`,
/// when given, are the first fits of every span (others[e] the span's own, made on the samples)
/// and `kept` the samples each kept; `kept_out` receives the samples this fit kept.
GaussianFit fit_echo(const WaveformConfig& config, const Waveform& waveform,
                     const std::vector<EchoSpan>& spans, const std::vector<GaussianFit>& others,
                     const std::vector<FitSamples>& kept, std::size_t e, FitScratch& scratch,
                     FitSamples& kept_out) {
    const auto& y = waveform.samples_w;
    const EchoSpan& span = spans[e];
    if (!others.empty() && others_negligible(waveform, span, others, e, kept[e])) {
        kept_out = kept[e];
        return others[e];
    }
    GaussianFit fit{waveform.time_ns(span.top), y[span.top], config.pulse_fwhm_ns / kFwhmPerSigma};
    // The others that are not 0 somewhere on the span, in order: subtracting the rest (and the
    // echo's own) would subtract exactly 0, which leaves every sample as it is.
    std::vector<std::size_t>& near = scratch.near;
    near.clear();
    const double lo_ns = waveform.time_ns(span.lo), hi_ns = waveform.time_ns(span.hi);
    for (std::size_t o = 0; o < others.size(); ++o) {
        if (o != e && !others[o].zero_on(lo_ns, hi_ns)) {
            near.push_back(o);
        }
    }
    if (!others.empty() && near.empty()) {
        kept_out = kept[e];
        return others[e];  // the residual is the samples: the fit is the first one, again
    }
    const auto residual = [&](std::size_t m) {
        double v = y[m];
        const double t_ns = waveform.time_ns(m);
        for (const std::size_t o : near) {
            v = minus_fit(v, others[o], t_ns);
        }
        return v;
    };
    if (!fit_gaussian(waveform, span, residual, scratch, fit, kept_out)) {
        fit = GaussianFit{waveform.time_ns(span.top), y[span.top],
                          config.pulse_fwhm_ns / kFwhmPerSigma};
    }
    return fit;
}

/// The echo of `span` with `fit`: energy over the span (its end samples, shared with the
/// neighbours, counted half).
Echo make_echo(const WaveformConfig& config, const Waveform& waveform, const EchoSpan& span,
               const GaussianFit& fit) {
    const auto& y = waveform.samples_w;
    double sum = 0.5 * (y[span.lo] + y[span.hi]);
    for (std::size_t j = span.lo + 1; j < span.hi; ++j) {
        sum += y[j];
    }
    const double sigma_p = config.pulse_fwhm_ns / kFwhmPerSigma;
    Echo e;
    e.range_m = fit.centre_ns / round_trip_ns_per_m();
    e.amplitude_w = fit.amplitude;
    e.width_ns = fit.sigma_ns * kFwhmPerSigma;
    e.power_w = sum * waveform.bin_ns / (sigma_p * kSqrtTwoPi);
    return e;
}

/// The echoes' spans: local maxima merged unless min_separation apart with a min_dip dip.
void find_spans(const WaveformConfig& config, const Waveform& waveform,
                std::vector<EchoSpan>& spans) {
    const double* const y = waveform.samples_w.data();
    const std::size_t n = waveform.samples_w.size();
    const double min_sep_bins =
        config.min_separation_or_default_m() * round_trip_ns_per_m() / waveform.bin_ns;
    const double keep = 1.0 - config.min_dip;
    // The lowest sample after the last span's top up to k (the first of equal ones; the top
    // itself when none is lower), kept as k advances.
    std::size_t valley = 0;
    double valley_w = std::numeric_limits<double>::infinity();  // y[valley] once a span exists
    for (std::size_t k = 1; k + 1 < n; ++k) {
        const double yk = y[k];
        if (yk < valley_w) {
            valley = k;
            valley_w = yk;
        }
        if (!(yk > y[k - 1] && yk >= y[k + 1])) {
            continue;
        }
        if (spans.empty()) {
            spans.push_back({0, n - 1, k});
            valley = k;
            valley_w = yk;
            continue;
        }
        EchoSpan& last = spans.back();
        const bool far = static_cast<double>(k - last.top) >= min_sep_bins;
        if (far && valley_w < keep * std::min(y[last.top], yk)) {
            last.hi = valley;
            spans.push_back({valley, n - 1, k});
            valley = k;
            valley_w = y[k];
        } else if (y[k] > y[last.top]) {
            last.top = k;
            valley = k;
            valley_w = y[k];
        }
    }
}

/// What detect_echoes works in: the spans, their fits and the first fits of the refit.
struct DetectScratch {
    std::vector<EchoSpan> spans;
    std::vector<GaussianFit> fits, first;
    std::vector<FitSamples> kept;  ///< the samples each first fit kept
    FitScratch fit;
};

}  // namespace

std::vector<std::string> WaveformConfig::validate() const {
    std::vector<std::string> p;
    if (!(pulse_fwhm_ns > 0) || !std::isfinite(pulse_fwhm_ns)) {
        p.emplace_back("waveform: pulse_fwhm_ns must be positive");
    }
    if (!(bin_ns > 0) || !std::isfinite(bin_ns)) {
        p.emplace_back("waveform: bin_ns must be positive");
    } else if (bin_ns > pulse_fwhm_ns / 2.0) {
        p.emplace_back("waveform: bin_ns must be at most pulse_fwhm_ns / 2");
    }
    if (!std::isfinite(min_separation_m) || min_separation_m > 1e4) {
        p.emplace_back("waveform: min_separation_m must be at most 10000 (negative: automatic)");
    }
    if (!(min_dip >= 0) || !(min_dip < 1)) {
        p.emplace_back("waveform: min_dip must be in [0, 1)");
    }
    return p;
}

double WaveformConfig::min_separation_or_default_m() const {
    return min_separation_m >= 0 ? min_separation_m : pulse_fwhm_ns / (2.0 * round_trip_ns_per_m());
}

void build_waveform(const WaveformConfig& config, std::span<const EchoContribution> contributions,
                    Waveform& out) {
    build_waveform(config, contributions, BinnedEcho{}, out);
}

void build_waveform(const WaveformConfig& config, std::span<const EchoContribution> contributions,
                    const BinnedEcho& binned, Waveform& out) {
    out.bin_ns = config.bin_ns;
    out.first_bin = 0;
    out.samples_w.clear();
    if (contributions.empty() && binned.empty()) {
        return;
    }
    const double sigma_p = config.pulse_fwhm_ns / kFwhmPerSigma;
    const auto sigma_of = [sigma_p](const EchoContribution& c) {
        return c.sigma_ns > 0 ? c.sigma_ns : sigma_p;
    };
    double t_lo = contributions.empty() ? binned.first_range_m : contributions[0].range_m;
    double t_hi = t_lo, sigma_max = 0.0;
    if (!binned.empty()) {
        t_lo = std::min(t_lo, binned.first_range_m);
        t_hi = std::max(t_hi, binned.last_range_m);
        sigma_max = sigma_p;
    }
    // One batch (a pulse's sub-rays): its quotients' inputs taken in the same loop.
    RunQuotients q;
    const bool one_batch = contributions.size() <= kBatch;
    std::size_t count = 0;
    const auto take = [&](const EchoContribution& c, double sigma) {
        q.t[count] = c.range_m * round_trip_ns_per_m();
        q.sigma[count] = sigma;
        q.amplitude[count] = c.power_w;
        q.stretched[count] = c.sigma_ns > 0;
        ++count;
    };
    for (const auto& c : contributions) {
        t_lo = std::min(t_lo, c.range_m);
        t_hi = std::max(t_hi, c.range_m);
        const double sigma = sigma_of(c);
        sigma_max = std::max(sigma_max, sigma);
        if (one_batch) {
            take(c, sigma);
        }
    }
    t_lo = t_lo * round_trip_ns_per_m() - 5.0 * sigma_max;
    t_hi = t_hi * round_trip_ns_per_m() + 5.0 * sigma_max;
    const std::int64_t first = floor_to_int(t_lo / config.bin_ns);
    const std::int64_t last = ceil_to_int(t_hi / config.bin_ns);
    out.first_bin = first;
    out.samples_w.assign(static_cast<std::size_t>(last - first + 1), 0.0);
    const auto add = [&] {  // the runs of q's count contributions
        GaussianRun runs[kBatch];
        make_runs(q, count, out.bin_ns, sigma_p, first, last, runs);
        add_runs(out, runs, count);
        count = 0;
    };
    for (std::size_t i = 0; !one_batch && i < contributions.size(); ++i) {
        take(contributions[i], sigma_of(contributions[i]));
        if (count == kBatch) {
            add();
        }
    }
    add();
    // The binned pulses' bins lie inside: their extent counted above with sigma_p <= sigma_max.
    if (!binned.empty()) {
        const std::int64_t at = binned.first_bin - first;
        assert(at >= 0 && at + static_cast<std::int64_t>(binned.samples_w.size()) <=
                              static_cast<std::int64_t>(out.samples_w.size()));
        double* y = out.samples_w.data() + at;
        for (const double v : binned.samples_w) {
            *y++ += v;
        }
    }
}

void detect_echoes(const WaveformConfig& config, const Waveform& waveform, double threshold_w,
                   std::vector<Echo>& out) {
    detect_echoes(config, waveform, threshold_w, 0.0, out);
}

void detect_echoes(const WaveformConfig& config, const Waveform& waveform, double threshold_w,
                   double unfitted_below_w, std::vector<Echo>& out) {
    assert(!(unfitted_below_w > threshold_w));
    if (waveform.samples_w.size() < 3) {
        return;
    }
    // The working space, kept per thread: no allocation per pulse once it has grown.
    thread_local DetectScratch work;
    std::vector<EchoSpan>& spans = work.spans;
    std::vector<GaussianFit>& fits = work.fits;
    FitScratch& scratch = work.fit;
    std::vector<FitSamples>& kept = work.kept;
    spans.clear();
    fits.clear();
    find_spans(config, waveform, spans);
    kept.resize(spans.size());
    // A span whose top is below unfitted_below_w (the weather's): the pulse through its top.
    const auto unfitted = [&](std::size_t e) {
        return waveform.samples_w[spans[e].top] < unfitted_below_w;
    };
    for (std::size_t e = 0; e < spans.size(); ++e) {
        fits.push_back(unfitted(e)
                           ? GaussianFit{waveform.time_ns(spans[e].top),
                                         waveform.samples_w[spans[e].top],
                                         config.pulse_fwhm_ns / kFwhmPerSigma}
                           : fit_echo(config, waveform, spans, {}, {}, e, scratch, kept[e]));
    }
    // Separate echoes overlap: refit each on the samples less its neighbours' first fits.
    if (spans.size() > 1) {
        std::vector<GaussianFit>& first = work.first;
        first = fits;
        FitSamples unused;
        for (std::size_t e = 0; e < spans.size(); ++e) {
            if (!unfitted(e)) {
                fits[e] = fit_echo(config, waveform, spans, first, kept, e, scratch, unused);
            }
        }
    }
    for (std::size_t e = 0; e < spans.size(); ++e) {
        if (fits[e].amplitude >= threshold_w) {
            out.push_back(make_echo(config, waveform, spans[e], fits[e]));
        }
    }
}

double gaussian_pulse_peak_power_w(double energy_j, double fwhm_ns) {
    return energy_j / (fwhm_ns * 1e-9 * std::sqrt(std::numbers::pi / (4.0 * std::numbers::ln2)));
}

}  // namespace beamtrace
