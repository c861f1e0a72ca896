// Which cell of a raster a coordinate falls in, for the sinks that bin points (preview.png).
#pragma once

#include <cmath>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace beamtrace::detail {

/// floor(d / cell), by a multiplication with per_cell = 1 / cell (a division per coordinate was
/// half of the preview's time). The product is within 2^-52 (relative) of the quotient, so the
/// two have the same floor unless the product lies within 2^-49 of a whole number, where the
/// division decides: always the same cell as dividing.
[[nodiscard]] inline double cells_floor(double d, double cell, double per_cell) {
    const double q = d * per_cell;
    const double f = std::floor(q);
    const double margin = std::abs(q) * 0x1p-49;
    if (q - f > margin && f + 1.0 - q > margin) {
        return f;
    }
    return std::floor(d / cell);  // near a cell's edge, at zero, infinite or NaN
}

/// cells_floor() of two coordinates, d0 and d1, into out[0] and out[1]: the same doubles, both
/// products' floors taken at once in SSE2 lanes (a truncation by conversion, exact below 2^31)
/// where both are clear of a cell's edge; otherwise (edges, zero, 2^31 cells or more, NaN) each
/// by cells_floor().
inline void cells_floor_pair(double d0, double d1, double cell, double per_cell, double out[2]) {
#if defined(__SSE2__)
    const __m128d q = _mm_mul_pd(_mm_set_pd(d1, d0), _mm_set1_pd(per_cell));
    const __m128d aq = _mm_andnot_pd(_mm_set1_pd(-0.0), q);
    const __m128d one = _mm_set1_pd(1.0);
    const __m128d t = _mm_cvtepi32_pd(_mm_cvttpd_epi32(q));
    const __m128d f = _mm_sub_pd(t, _mm_and_pd(_mm_cmpgt_pd(t, q), one));
    const __m128d margin = _mm_mul_pd(aq, _mm_set1_pd(0x1p-49));
    const __m128d clear = _mm_and_pd(_mm_cmpgt_pd(_mm_sub_pd(q, f), margin),
                                     _mm_cmpgt_pd(_mm_sub_pd(_mm_add_pd(f, one), q), margin));
    if (_mm_movemask_pd(_mm_and_pd(clear, _mm_cmplt_pd(aq, _mm_set1_pd(0x1p31)))) == 3) {
        _mm_storeu_pd(out, f);
        return;
    }
#endif
    out[0] = cells_floor(d0, cell, per_cell);
    out[1] = cells_floor(d1, cell, per_cell);
}

}  // namespace beamtrace::detail
