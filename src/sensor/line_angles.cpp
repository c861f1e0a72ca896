#include "sensor/detail/line_angles.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include "sensor/detail/index_quad.hpp"
#define BEAMTRACE_LINE_ANGLES_AVX2 1
#endif

namespace beamtrace::detail {

void line_angles_scalar(const LineAngleParams& p, std::uint64_t first, std::size_t count,
                        double* angle_deg, double* time_s) {
    for (std::size_t j = 0; j < count; ++j) {
        const std::uint64_t i = first + j;
        const double lines = lines_of_pulse(p, i);
        angle_deg[j] = p.triangle ? triangle_deg(p.max_deg, lines) : sawtooth_deg(p.max_deg, lines);
        time_s[j] = p.start_s + static_cast<double>(i) / p.pulse_rate_hz;
    }
}

#if BEAMTRACE_LINE_ANGLES_AVX2
namespace {

/// sawtooth_deg() or triangle_deg() lane by lane: each product and sum rounded alone (no FMA).
template <bool Triangle>
__attribute__((target("avx2"))) void angle_quads(const LineAngleParams& p, std::uint64_t first,
                                                 std::size_t quads, double* angle_deg,
                                                 double* time_s) {
    const __m256d start = _mm256_set1_pd(p.start_s), rate = _mm256_set1_pd(p.pulse_rate_hz);
    const __m256d lines_per_s = _mm256_set1_pd(p.lines_per_s);
    const __m256d a = _mm256_set1_pd(p.max_deg), minus_a = _mm256_set1_pd(-p.max_deg);
    const __m256d two_a = _mm256_set1_pd(2.0 * p.max_deg);
    const __m256d half = _mm256_set1_pd(0.5), one = _mm256_set1_pd(1.0);
    const __m256d four = _mm256_set1_pd(4.0), sign = _mm256_set1_pd(-0.0);
    for (std::size_t q = 0; q < quads; ++q) {
        const __m256d id = index_quad(first + 4 * q);
        const __m256d lines = _mm256_div_pd(_mm256_mul_pd(id, lines_per_s), rate);
        __m256d angle;
        if constexpr (Triangle) {
            const __m256d h = _mm256_mul_pd(half, lines);
            const __m256d f = _mm256_sub_pd(h, _mm256_floor_pd(h));
            const __m256d d = _mm256_andnot_pd(sign, _mm256_sub_pd(f, half));
            angle = _mm256_mul_pd(a, _mm256_sub_pd(one, _mm256_mul_pd(four, d)));
        } else {
            const __m256d f = _mm256_sub_pd(lines, _mm256_floor_pd(lines));
            angle = _mm256_add_pd(minus_a, _mm256_mul_pd(two_a, f));
        }
        _mm256_storeu_pd(angle_deg + 4 * q, angle);
        _mm256_storeu_pd(time_s + 4 * q, _mm256_add_pd(start, _mm256_div_pd(id, rate)));
    }
}

}  // namespace
#endif

std::size_t line_angles_lanes(const LineAngleParams& p, std::uint64_t first, std::size_t count,
                              double* angle_deg, double* time_s) {
#if BEAMTRACE_LINE_ANGLES_AVX2
    if (!__builtin_cpu_supports("avx2") || first >= kExactIndices ||
        count >= kExactIndices - first) {
        return 0;
    }
    const std::size_t quads = count / 4;
    if (p.triangle) {
        angle_quads<true>(p, first, quads, angle_deg, time_s);
    } else {
        angle_quads<false>(p, first, quads, angle_deg, time_s);
    }
    return 4 * quads;
#else
    (void)p, (void)first, (void)count, (void)angle_deg, (void)time_s;
    return 0;
#endif
}

}  // namespace beamtrace::detail
