#include "io/sinks/preview_shading.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "beamtrace/core/vec3.hpp"
#include "beamtrace/io/colormap.hpp"
#include "core/simd_level.hpp"
#include "io/detail/round_int32.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define BEAMTRACE_PREVIEW_AVX2 1
#endif

namespace beamtrace::detail {

namespace {

/// The light's direction, from the north-west and 45 degrees up (unit length).
Vec3d preview_light() {
    return normalize(Vec3d{-1.0, 1.0, std::sqrt(2.0)});
}

/// Pixel x of the row (not empty) into p[0..2].
void shade_pixel(const PreviewRows& r, const PreviewShading& s, const Vec3d& light, int x,
                 std::uint8_t* p) {
    const float own = r.row[x];
    const auto z = [&](float h) { return static_cast<double>(h == r.empty ? own : h); };
    const int west = x > 0 ? x - 1 : 0, east = x + 1 < r.width ? x + 1 : r.width - 1;
    const double two_cells = 2.0 * s.cell_m;
    const double gx = (z(r.row[east]) - z(r.row[west])) / two_cells;  // east
    const double gy = (z(r.up[x]) - z(r.down[x])) / two_cells;        // north
    const Vec3d n = normalize(Vec3d{-gx, -gy, 1.0});
    const double shade = std::clamp(0.35 + 0.65 * std::max(0.0, dot(n, light)) / light.z, 0.0, 1.0);
    const auto jet = jet_color(s.span > 0 ? (static_cast<double>(own) - s.z_lo) / s.span : 0.5);
    for (int k = 0; k < 3; ++k) {
        p[k] = static_cast<std::uint8_t>(round_to_int32(jet[static_cast<std::size_t>(k)] * shade));
    }
}

#if defined(BEAMTRACE_PREVIEW_AVX2)

/// round_to_int32() in lanes (values finite, non-negative): the truncation plus one where the
/// fraction is at least 0.5. The same doubles.
__attribute__((target("avx2"))) __m256d round_half_up_lanes(__m256d v) {
    const __m256d i = _mm256_round_pd(v, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
    const __m256d up = _mm256_cmp_pd(_mm256_sub_pd(v, i), _mm256_set1_pd(0.5), _CMP_GE_OQ);
    return _mm256_add_pd(i, _mm256_and_pd(up, _mm256_set1_pd(1.0)));
}

/// std::clamp(v, 0, 1) in lanes (no NaN): lo where v < lo, hi where hi < v, else v itself (so
/// -0 stays -0, as std::clamp keeps it).
__attribute__((target("avx2"))) __m256d clamp01_lanes(__m256d v) {
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
    v = _mm256_blendv_pd(v, zero, _mm256_cmp_pd(v, zero, _CMP_LT_OQ));
    return _mm256_blendv_pd(v, one, _mm256_cmp_pd(one, v, _CMP_LT_OQ));
}

/// One channel of jet_color() in lanes: a trapezoid of height 1 centred at `centre`, 0.75 wide at
/// the top, times 255, rounded.
__attribute__((target("avx2"))) __m256d jet_channel_lanes(__m256d t, double centre) {
    const __m256d d = _mm256_mul_pd(_mm256_set1_pd(4.0), _mm256_sub_pd(t, _mm256_set1_pd(centre)));
    const __m256d abs_d = _mm256_andnot_pd(_mm256_set1_pd(-0.0), d);
    const __m256d c = clamp01_lanes(_mm256_sub_pd(_mm256_set1_pd(1.5), abs_d));
    return round_half_up_lanes(_mm256_mul_pd(c, _mm256_set1_pd(255.0)));
}

/// The shade of four pixels from their heights and their neighbours' (empty ones replaced).
__attribute__((target("avx2"))) __m256d shade_lanes(__m256d east, __m256d west, __m256d up,
                                                    __m256d down, __m256d two_cells,
                                                    const Vec3d& light) {
    const __m256d gx = _mm256_div_pd(_mm256_sub_pd(east, west), two_cells);
    const __m256d gy = _mm256_div_pd(_mm256_sub_pd(up, down), two_cells);
    // normalize({-gx, -gy, 1}): ((gx gx + gy gy) + 1 1), its root, one over it, each scaled.
    const __m256d one = _mm256_set1_pd(1.0);
    const __m256d len2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(gx, gx), _mm256_mul_pd(gy, gy)),
                                       _mm256_mul_pd(one, one));
    const __m256d inv = _mm256_div_pd(one, _mm256_sqrt_pd(len2));
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256d nx = _mm256_mul_pd(_mm256_xor_pd(gx, sign), inv);
    const __m256d ny = _mm256_mul_pd(_mm256_xor_pd(gy, sign), inv);
    const __m256d nz = _mm256_mul_pd(one, inv);
    const __m256d d = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(nx, _mm256_set1_pd(light.x)),
                                                  _mm256_mul_pd(ny, _mm256_set1_pd(light.y))),
                                    _mm256_mul_pd(nz, _mm256_set1_pd(light.z)));
    // std::max(0.0, d): d where 0 < d, else +0 (maxpd gives its second operand unless d > 0).
    const __m256d lit = _mm256_max_pd(d, _mm256_setzero_pd());
    const __m256d s = _mm256_add_pd(
        _mm256_set1_pd(0.35),
        _mm256_div_pd(_mm256_mul_pd(_mm256_set1_pd(0.65), lit), _mm256_set1_pd(light.z)));
    return clamp01_lanes(s);
}

/// Heights of pixels [x, x + 4) of `row` as doubles, empty ones replaced by `own`'s.
__attribute__((target("avx2"))) __m256d heights_lanes(const float* row, __m128 own, __m128 empty) {
    const __m128 h = _mm_loadu_ps(row);
    return _mm256_cvtps_pd(_mm_blendv_ps(h, own, _mm_cmpeq_ps(h, empty)));
}

/// Pixels [x, x + 4) (1 <= x, x + 4 < width) into out (the crop's row at x0).
__attribute__((target("avx2"))) void shade_four(const PreviewRows& r, const PreviewShading& s,
                                                const Vec3d& light, int x, int x0,
                                                std::uint8_t* out) {
    const __m128 empty = _mm_set1_ps(r.empty);
    const __m128 own_f = _mm_loadu_ps(r.row + x);
    const int occupied = 15 & ~_mm_movemask_ps(_mm_cmpeq_ps(own_f, empty));
    if (occupied == 0) {
        return;
    }
    const __m256d own = _mm256_cvtps_pd(own_f);
    const __m256d shade = shade_lanes(
        heights_lanes(r.row + x + 1, own_f, empty), heights_lanes(r.row + x - 1, own_f, empty),
        heights_lanes(r.up + x, own_f, empty), heights_lanes(r.down + x, own_f, empty),
        _mm256_set1_pd(2.0 * s.cell_m), light);
    __m256d t = s.span > 0 ? _mm256_div_pd(_mm256_sub_pd(own, _mm256_set1_pd(s.z_lo)),
                                           _mm256_set1_pd(s.span))
                           : _mm256_set1_pd(0.5);
    t = _mm256_blendv_pd(t, _mm256_setzero_pd(), _mm256_cmp_pd(t, t, _CMP_UNORD_Q));
    t = clamp01_lanes(t);
    alignas(16) std::int32_t ch[3][4];
    const double centres[3] = {0.75, 0.5, 0.25};
    for (int k = 0; k < 3; ++k) {
        const __m256d v =
            round_half_up_lanes(_mm256_mul_pd(jet_channel_lanes(t, centres[k]), shade));
        _mm_store_si128(reinterpret_cast<__m128i*>(ch[k]), _mm256_cvttpd_epi32(v));
    }
    for (int i = 0; i < 4; ++i) {
        if ((occupied >> i & 1) != 0) {
            std::uint8_t* p = out + 3 * static_cast<std::size_t>(x + i - x0);
            p[0] = static_cast<std::uint8_t>(ch[0][i]);
            p[1] = static_cast<std::uint8_t>(ch[1][i]);
            p[2] = static_cast<std::uint8_t>(ch[2][i]);
        }
    }
}

/// shade_preview_row() with four pixels at a time where their neighbours are inside the row.
__attribute__((target("avx2"))) void shade_row_avx2(const PreviewRows& r, const PreviewShading& s,
                                                    int x0, int x1, std::uint8_t* out) {
    const Vec3d light = preview_light();
    const int lanes_end = std::min(x1, r.width - 1);  // x + 4 <= lanes_end: x + 4 < width
    int x = x0;
    for (; x < x1 && x < 1; ++x) {
        if (r.row[x] != r.empty) {
            shade_pixel(r, s, light, x, out + 3 * static_cast<std::size_t>(x - x0));
        }
    }
    for (; x + 4 <= lanes_end; x += 4) {
        shade_four(r, s, light, x, x0, out);
    }
    for (; x < x1; ++x) {
        if (r.row[x] != r.empty) {
            shade_pixel(r, s, light, x, out + 3 * static_cast<std::size_t>(x - x0));
        }
    }
}

#endif

}  // namespace

void shade_preview_row_scalar(const PreviewRows& rows, const PreviewShading& shading, int x0,
                              int x1, std::uint8_t* out) {
    const Vec3d light = preview_light();
    for (int x = x0; x < x1; ++x) {
        if (rows.row[x] != rows.empty) {
            shade_pixel(rows, shading, light, x, out + 3 * static_cast<std::size_t>(x - x0));
        }
    }
}

void shade_preview_row(const PreviewRows& rows, const PreviewShading& shading, int x0, int x1,
                       std::uint8_t* out) {
#if defined(BEAMTRACE_PREVIEW_AVX2)
    if (cpu_simd_level() != SimdLevel::scalar) {
        shade_row_avx2(rows, shading, x0, x1, out);
        return;
    }
#endif
    shade_preview_row_scalar(rows, shading, x0, x1, out);
}

}  // namespace beamtrace::detail
