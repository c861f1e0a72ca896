#include "io/sinks/preview_cells.hpp"

#include <algorithm>
#include <limits>

#include "core/simd_level.hpp"
#include "io/sinks/raster_cells.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define BEAMTRACE_PREVIEW_CELLS_AVX2 1
#endif

namespace beamtrace::detail {

namespace {

/// Points [begin, end) of preview_cells(), found one at a time; stores from pixel[n] on.
std::size_t cells_scalar(std::span<const BlockPoint> points, std::size_t begin, std::size_t end,
                         const PreviewGrid& g, std::uint32_t* pixel, float* height, std::size_t n) {
    for (std::size_t i = begin; i < end; ++i) {
        const BlockPoint& p = points[i];
        double uv[2];
        cells_floor_pair(p.x - g.west, g.north - p.y, g.cell_m, g.per_cell, uv);
        const double u = uv[0], v = uv[1];
        if (u >= 0 && v >= 0 && u < g.width && v < g.height) {
            pixel[n] = static_cast<std::uint32_t>(v * g.width + u);
            height[n] = static_cast<float>(p.z) + 0.0f;
            ++n;
        }
    }
    return n;
}

/// row_hits() of pixels [x, width), on from `h` (the hits of [0, x)).
RowHits hits_scalar(const float* row, int x, int width, float empty, RowHits h) {
    for (; x < width; ++x) {
        const float z = row[x];
        if (z == empty) {
            continue;
        }
        h.lo = h.first < 0 ? z : std::min(h.lo, z);
        h.hi = h.first < 0 ? z : std::max(h.hi, z);
        h.first = h.first < 0 ? x : h.first;
        h.last = x;
    }
    return h;
}

#if defined(BEAMTRACE_PREVIEW_CELLS_AVX2)

/// row_hits() with eight pixels at a time: the lowest of the hits (empty ones as +infinity) and
/// the highest (empty ones are below every height); minps and maxps give the same value as
/// std::min and std::max in any order, as a row holds no NaN and no -0 (heights are raised
/// from -infinity, -0 taken as +0).
__attribute__((target("avx2"))) RowHits hits_avx2(const float* row, int width, float empty) {
    const __m256 none = _mm256_set1_ps(empty);
    const __m256 inf = _mm256_set1_ps(std::numeric_limits<float>::infinity());
    __m256 lo = inf, hi = none;
    int first = -1, last = -1, x = 0;
    for (; x + 8 <= width; x += 8) {
        const __m256 z = _mm256_loadu_ps(row + x);
        const __m256 is_empty = _mm256_cmp_ps(z, none, _CMP_EQ_OQ);
        const int hits = 255 & ~_mm256_movemask_ps(is_empty);
        if (hits == 0) {
            continue;
        }
        first = first < 0 ? x + __builtin_ctz(static_cast<unsigned>(hits)) : first;
        last = x + 31 - __builtin_clz(static_cast<unsigned>(hits));
        lo = _mm256_min_ps(lo, _mm256_blendv_ps(z, inf, is_empty));
        hi = _mm256_max_ps(hi, z);
    }
    alignas(32) float los[8], his[8];
    _mm256_store_ps(los, lo);
    _mm256_store_ps(his, hi);
    RowHits h{first, last, *std::min_element(los, los + 8), *std::max_element(his, his + 8)};
    if (first < 0) {
        h = RowHits{};
    }
    return hits_scalar(row, x, width, empty, h);
}

/// cells_floor() in lanes: the product's floor where it is clear of a cell's edge (as
/// cells_floor() decides it), else the quotient's floor (NaN stays NaN).
__attribute__((target("avx2"))) __m256d cells_floor_lanes(__m256d d, __m256d cell,
                                                          __m256d per_cell) {
    const __m256d q = _mm256_mul_pd(d, per_cell);
    const __m256d f = _mm256_round_pd(q, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    const __m256d margin =
        _mm256_mul_pd(_mm256_andnot_pd(_mm256_set1_pd(-0.0), q), _mm256_set1_pd(0x1p-49));
    const __m256d clear = _mm256_and_pd(
        _mm256_cmp_pd(_mm256_sub_pd(q, f), margin, _CMP_GT_OQ),
        _mm256_cmp_pd(_mm256_sub_pd(_mm256_add_pd(f, _mm256_set1_pd(1.0)), q), margin, _CMP_GT_OQ));
    if (_mm256_movemask_pd(clear) == 15) {
        return f;
    }
    const __m256d exact =
        _mm256_round_pd(_mm256_div_pd(d, cell), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    return _mm256_blendv_pd(exact, f, clear);
}

/// preview_cells() with four points at a time: their x, y, z (and GPS time, unused) loaded whole
/// and transposed into lanes.
__attribute__((target("avx2"))) std::size_t cells_avx2(std::span<const BlockPoint> points,
                                                       const PreviewGrid& g, std::uint32_t* pixel,
                                                       float* height) {
    const __m256d west = _mm256_set1_pd(g.west), north = _mm256_set1_pd(g.north);
    const __m256d cell = _mm256_set1_pd(g.cell_m), per_cell = _mm256_set1_pd(g.per_cell);
    const __m256d width = _mm256_set1_pd(g.width), rows = _mm256_set1_pd(g.height);
    const __m256d zero = _mm256_setzero_pd();
    std::size_t n = 0, i = 0;
    for (; i + 4 <= points.size(); i += 4) {
        const __m256d p0 = _mm256_loadu_pd(&points[i].x), p1 = _mm256_loadu_pd(&points[i + 1].x);
        const __m256d p2 = _mm256_loadu_pd(&points[i + 2].x);
        const __m256d p3 = _mm256_loadu_pd(&points[i + 3].x);
        // (x0 x1 | z0 z1), (y0 y1 | t0 t1), and the same of points 2 and 3.
        const __m256d xz01 = _mm256_unpacklo_pd(p0, p1), yt01 = _mm256_unpackhi_pd(p0, p1);
        const __m256d xz23 = _mm256_unpacklo_pd(p2, p3), yt23 = _mm256_unpackhi_pd(p2, p3);
        const __m256d x = _mm256_permute2f128_pd(xz01, xz23, 0x20);
        const __m256d z = _mm256_permute2f128_pd(xz01, xz23, 0x31);
        const __m256d y = _mm256_permute2f128_pd(yt01, yt23, 0x20);
        const __m256d u = cells_floor_lanes(_mm256_sub_pd(x, west), cell, per_cell);
        const __m256d v = cells_floor_lanes(_mm256_sub_pd(north, y), cell, per_cell);
        const __m256d on = _mm256_and_pd(
            _mm256_and_pd(_mm256_cmp_pd(u, zero, _CMP_GE_OQ), _mm256_cmp_pd(v, zero, _CMP_GE_OQ)),
            _mm256_and_pd(_mm256_cmp_pd(u, width, _CMP_LT_OQ), _mm256_cmp_pd(v, rows, _CMP_LT_OQ)));
        const int mask = _mm256_movemask_pd(on);
        if (mask == 0) {
            continue;
        }
        // Off the grid, a lane's pixel is whatever the conversion gives; it is not kept.
        const __m256d at = _mm256_blendv_pd(zero, _mm256_add_pd(_mm256_mul_pd(v, width), u), on);
        alignas(16) std::int32_t px[4];
        alignas(16) float h[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(px), _mm256_cvttpd_epi32(at));
        _mm_store_ps(h, _mm_add_ps(_mm256_cvtpd_ps(z), _mm_setzero_ps()));
        for (int k = 0; k < 4; ++k) {
            pixel[n] = static_cast<std::uint32_t>(px[k]);
            height[n] = h[k];
            n += static_cast<std::size_t>(mask >> k & 1);
        }
    }
    return cells_scalar(points, i, points.size(), g, pixel, height, n);
}

#endif

}  // namespace

std::size_t preview_cells_scalar(std::span<const BlockPoint> points, const PreviewGrid& grid,
                                 std::uint32_t* pixel, float* height) {
    return cells_scalar(points, 0, points.size(), grid, pixel, height, 0);
}

RowHits row_hits_scalar(const float* row, int width, float empty) {
    return hits_scalar(row, 0, width, empty, RowHits{});
}

RowHits row_hits(const float* row, int width, float empty) {
#if defined(BEAMTRACE_PREVIEW_CELLS_AVX2)
    if (cpu_simd_level() != SimdLevel::scalar) {
        return hits_avx2(row, width, empty);
    }
#endif
    return row_hits_scalar(row, width, empty);
}

std::size_t preview_cells(std::span<const BlockPoint> points, const PreviewGrid& grid,
                          std::uint32_t* pixel, float* height) {
#if defined(BEAMTRACE_PREVIEW_CELLS_AVX2)
    if (cpu_simd_level() != SimdLevel::scalar) {
        return cells_avx2(points, grid, pixel, height);
    }
#endif
    return preview_cells_scalar(points, grid, pixel, height);
}

}  // namespace beamtrace::detail
