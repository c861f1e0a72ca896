#include "detail/view_trace_simd.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define BEAMTRACE_VIEW_AVX2 1
#else
#define BEAMTRACE_VIEW_AVX2 0
#endif

#include <stdexcept>

namespace beamtrace::detail {

#if BEAMTRACE_VIEW_AVX2

bool avx2_available() {
    static const bool available = __builtin_cpu_supports("avx2") != 0;
    return available;
}

namespace {

#define BT_AVX2 __attribute__((target("avx2"), always_inline)) inline

using I = __m256i;
using D = __m256d;

constexpr int kLanes = 4;

/// v as doubles, exactly, for 0 <= v < 2^52.
BT_AVX2 D to_double(I v) {
    const I magic = _mm256_set1_epi64x(0x4330000000000000);
    return _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(v, magic)),
                         _mm256_set1_pd(4503599627370496.0));
}
BT_AVX2 I as_mask(D compare) {
    return _mm256_castpd_si256(compare);
}
/// m (lanes all ones or zero) ? a : b.
BT_AVX2 I sel(I m, I a, I b) {
    return _mm256_blendv_epi8(b, a, m);
}
BT_AVX2 D sel(I m, D a, D b) {
    return _mm256_blendv_pd(b, a, _mm256_castsi256_pd(m));
}
BT_AVX2 I max64(I a, I b) {
    return sel(_mm256_cmpgt_epi64(a, b), a, b);
}
BT_AVX2 I min64(I a, I b) {
    return sel(_mm256_cmpgt_epi64(a, b), b, a);
}
BT_AVX2 I set1(std::int64_t v) {
    return _mm256_set1_epi64x(v);
}
BT_AVX2 I andnot(I a, I b) {
    return _mm256_andnot_si256(a, b);
}  // ~a & b
BT_AVX2 int lanes_of(I m) {
    return _mm256_movemask_pd(_mm256_castsi256_pd(m));
}

/// Trailing zero bits of v | 2^40 (levels to climb: far more than any traversal has).
BT_AVX2 I trailing_zeros(I v) {
    v = _mm256_or_si256(v, set1(std::int64_t{1} << 40));
    const I low = _mm256_and_si256(v, _mm256_sub_epi64(_mm256_setzero_si256(), v));
    const I bits = _mm256_castpd_si256(to_double(low));
    return _mm256_sub_epi64(_mm256_srli_epi64(bits, 52), set1(1023));
}

/// table[index] in the lanes of `enabled`, `fallback` elsewhere: four scalar loads (the gather
/// instructions are slow on CPUs with the Gather Data Sampling mitigation), lanes moved through
/// registers (a vector load of values just stored one by one would stall store forwarding).
BT_AVX2 I gather64(const std::int64_t* table, I index, int enabled, std::int64_t fallback) {
    const auto at = [&](std::int64_t i, int j) {
        return (enabled & (1 << j)) != 0 ? table[i] : fallback;
    };
    return _mm256_setr_epi64x(
        at(_mm256_extract_epi64(index, 0), 0), at(_mm256_extract_epi64(index, 1), 1),
        at(_mm256_extract_epi64(index, 2), 2), at(_mm256_extract_epi64(index, 3), 3));
}

/// The per-frame constants of the height lookup.
struct Lookup {
    const float* const* address;
    I n, n2, top, top1, shift, pyramid_base, pyramid_shift0;
};

/// height(level, x, y) of LevelTable for the lanes of `enabled` (kEmptyHeight elsewhere).
BT_AVX2 D heights(const Lookup& p, I level, I x, I y, I enabled) {
    // Sections' levels: slot (y >> sh) * n + (x >> sh), rows of 2^sh cells.
    const I sh = _mm256_sub_epi64(p.shift, level);
    const I slot =
        _mm256_add_epi64(_mm256_mul_epu32(_mm256_srlv_epi64(y, sh), p.n), _mm256_srlv_epi64(x, sh));
    const I entry_s = _mm256_add_epi64(_mm256_mul_epu32(level, p.n2), slot);
    const I m = _mm256_sub_epi64(_mm256_sllv_epi64(set1(1), sh), set1(1));
    const I off_s =
        _mm256_add_epi64(_mm256_sllv_epi64(_mm256_and_si256(y, m), sh), _mm256_and_si256(x, m));
    // The pyramid's levels: one table entry each, rows of 2^(shift0 - k) cells.
    const I k = _mm256_sub_epi64(level, p.top1);
    const I entry_p = _mm256_add_epi64(p.pyramid_base, k);
    const I off_p =
        _mm256_add_epi64(_mm256_sllv_epi64(y, _mm256_sub_epi64(p.pyramid_shift0, k)), x);
    const I in_sections = _mm256_cmpgt_epi64(p.top1, level);
    const I entry = sel(in_sections, entry_s, entry_p);
    const I off = sel(in_sections, off_s, off_p);
    const int on = lanes_of(enabled);
    const auto at = [&](int j, std::int64_t e, std::int64_t o) {
        const float* b = (on & (1 << j)) != 0 ? p.address[e] : nullptr;
        return b != nullptr ? b[o] : kEmptyHeight;
    };
    const __m128 h =
        _mm_setr_ps(at(0, _mm256_extract_epi64(entry, 0), _mm256_extract_epi64(off, 0)),
                    at(1, _mm256_extract_epi64(entry, 1), _mm256_extract_epi64(off, 1)),
                    at(2, _mm256_extract_epi64(entry, 2), _mm256_extract_epi64(off, 2)),
                    at(3, _mm256_extract_epi64(entry, 3), _mm256_extract_epi64(off, 3)));
    return _mm256_cvtps_pd(h);
}

/// The lanes' rays and walks, one array per field.
struct alignas(32) Lanes {
    double ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes];
    double inv_dx[kLanes], inv_dy[kLanes], t_max[kLanes], t[kLanes];
    std::int64_t cx[kLanes], cy[kLanes], level[kLanes], entered[kLanes];
    std::int64_t sx[kLanes], sy[kLanes], off_x[kLanes], off_y[kLanes];
    std::int64_t climb_x[kLanes], climb_y[kLanes], down[kLanes], active[kLanes];
    std::size_t ray[kLanes];

    void start(int j, const GridRay& r, std::size_t i, int top) {
        ox[j] = r.ox;
        oy[j] = r.oy;
        oz[j] = r.oz;
        dx[j] = r.dx;
        dy[j] = r.dy;
        dz[j] = r.dz;
        inv_dx[j] = r.inv_dx;
        inv_dy[j] = r.inv_dy;
        t_max[j] = r.t_max;
        t[j] = r.t_min;
        cx[j] = r.gx >> top;
        cy[j] = r.gy >> top;
        level[j] = top;
        entered[j] = -1;
        sx[j] = r.sx;
        sy[j] = r.sy;
        off_x[j] = r.sx > 0 ? 1 : 0;
        off_y[j] = r.sy > 0 ? 1 : 0;
        climb_x[j] = r.sx > 0 ? 0 : -1;
        climb_y[j] = r.sy > 0 ? 0 : -1;
        down[j] = r.dz < 0 ? -1 : 0;
        active[j] = -1;
        ray[j] = i;
    }
    /// A lane with no ray: disabled, with a harmless state.
    void stop(int j) {
        active[j] = 0;
        level[j] = 0;
        cx[j] = cy[j] = 0;
        off_x[j] = off_y[j] = 0;
        ox[j] = oy[j] = oz[j] = dz[j] = t[j] = 0.0;
        dx[j] = dy[j] = 1.0;
        inv_dx[j] = inv_dy[j] = 1.0;
        t_max[j] = 1.0;
    }
};

BT_AVX2 D load(const double* p) {
    return _mm256_load_pd(p);
}
BT_AVX2 I load(const std::int64_t* p) {
    return _mm256_load_si256(reinterpret_cast<const __m256i*>(p));
}
BT_AVX2 void store(double* p, D v) {
    _mm256_store_pd(p, v);
}
BT_AVX2 void store(std::int64_t* p, I v) {
    _mm256_store_si256(reinterpret_cast<__m256i*>(p), v);
}

__attribute__((target("avx2"))) void trace_avx2(const LevelTable& table, const GridRay* rays,
                                                std::size_t count, GridHit* hits,
                                                std::uint8_t* found) {
    const int top = table.section_top();
    const auto n = static_cast<std::int64_t>(table.sections_per_side());
    Lookup p{};
    p.address = table.address_table();
    p.n = set1(n);
    p.n2 = set1(n * n);
    p.top = set1(top);
    p.top1 = set1(top + 1);
    p.shift = set1(table.finest_shift());
    p.pyramid_base = set1(static_cast<std::int64_t>(table.pyramid_slot(0)));
    p.pyramid_shift0 = set1(table.root() > top ? table.row_shift(0) : 0);
    const I root = set1(table.root());
    const I zero = _mm256_setzero_si256();
    const I one = set1(1);
    const D empty = _mm256_set1_pd(static_cast<double>(kEmptyHeight));
    const I window = set1(table.cells(0));

    Lanes s;
    std::size_t next = 0;
    for (int j = 0; j < kLanes; ++j) {
        if (next < count) {
            s.start(j, rays[next], next, top);
            ++next;
        } else {
            s.stop(j);
        }
    }
    for (;;) {
        const I active = load(s.active);
        if (lanes_of(active) == 0) {
            break;
        }
        const D ox = load(s.ox), oy = load(s.oy), oz = load(s.oz);
        const D dx = load(s.dx), dy = load(s.dy), dz = load(s.dz);
        const D t = load(s.t), t_max = load(s.t_max);
        const I level = load(s.level), cx = load(s.cx), cy = load(s.cy);
        const I sx = load(s.sx), sy = load(s.sy);
        const I climb_x = load(s.climb_x), climb_y = load(s.climb_y);

        // The cell's exits and the ray's height over it (as trace_octant).
        const D bx = to_double(_mm256_sllv_epi64(_mm256_add_epi64(cx, load(s.off_x)), level));
        const D by = to_double(_mm256_sllv_epi64(_mm256_add_epi64(cy, load(s.off_y)), level));
        const D tx = _mm256_mul_pd(_mm256_sub_pd(bx, ox), load(s.inv_dx));
        const D ty = _mm256_mul_pd(_mm256_sub_pd(by, oy), load(s.inv_dy));
        const D t_out = _mm256_min_pd(ty, tx);        // std::min(tx, ty)
        const D t_end = _mm256_min_pd(t_max, t_out);  // std::min(t_out, t_max)
        const D h = heights(p, level, cx, cy, active);
        const D z = _mm256_add_pd(oz, _mm256_mul_pd(dz, sel(load(s.down), t_end, t)));
        const I below = _mm256_and_si256(as_mask(_mm256_cmp_pd(z, h, _CMP_LE_OQ)), active);
        const I hit = _mm256_and_si256(below, _mm256_cmpeq_epi64(level, zero));

        // Descend: the child under the ray at t.
        const I down_level = _mm256_sub_epi64(level, one);
        const D px = _mm256_add_pd(ox, _mm256_mul_pd(dx, t));
        const D py = _mm256_add_pd(oy, _mm256_mul_pd(dy, t));
        const I cx2 = _mm256_add_epi64(cx, cx), cy2 = _mm256_add_epi64(cy, cy);
        const I dcx = _mm256_sub_epi64(
            cx2, as_mask(_mm256_cmp_pd(
                     px, to_double(_mm256_sllv_epi64(_mm256_add_epi64(cx2, one), down_level)),
                     _CMP_GE_OQ)));
        const I dcy = _mm256_sub_epi64(
            cy2, as_mask(_mm256_cmp_pd(
                     py, to_double(_mm256_sllv_epi64(_mm256_add_epi64(cy2, one), down_level)),
                     _CMP_GE_OQ)));

        // Step: to the next cell; out of the window or past t_max ends the ray.
        const I step_x = as_mask(_mm256_cmp_pd(tx, ty, _CMP_LE_OQ));
        const I step_y = as_mask(_mm256_cmp_pd(ty, tx, _CMP_LE_OQ));
        I acx = _mm256_add_epi64(cx, _mm256_and_si256(sx, step_x));
        I acy = _mm256_add_epi64(cy, _mm256_and_si256(sy, step_y));
        // Cells per side at the level: ceil(window cells / 2^level), as LevelTable::cells.
        const I cells = _mm256_srlv_epi64(
            _mm256_sub_epi64(_mm256_add_epi64(window, _mm256_sllv_epi64(one, level)), one), level);
        const I out = _mm256_or_si256(
            _mm256_or_si256(
                as_mask(_mm256_cmp_pd(t_out, t_max, _CMP_GE_OQ)),
                _mm256_or_si256(_mm256_cmpgt_epi64(zero, acx), _mm256_cmpgt_epi64(zero, acy))),
            andnot(_mm256_and_si256(_mm256_cmpgt_epi64(cells, acx), _mm256_cmpgt_epi64(cells, acy)),
                   _mm256_set1_epi64x(-1)));
        const I miss = andnot(below, _mm256_and_si256(active, out));
        // Climb while the step left the parent: within the sections' levels always...
        const I kx = _mm256_and_si256(trailing_zeros(_mm256_xor_si256(acx, climb_x)), step_x);
        const I ky = _mm256_and_si256(trailing_zeros(_mm256_xor_si256(acy, climb_y)), step_y);
        const I room = max64(_mm256_sub_epi64(p.top, level), zero);
        const I k = min64(max64(kx, ky), room);
        I alevel = _mm256_add_epi64(level, k);
        acx = _mm256_srlv_epi64(acx, k);
        acy = _mm256_srlv_epi64(acy, k);
        // ... and into the pyramid only while its cell there is empty.
        I climbing = andnot(_mm256_or_si256(below, out), active);
        for (;;) {
            const I cross_x = _mm256_and_si256(
                step_x,
                _mm256_cmpeq_epi64(_mm256_and_si256(_mm256_xor_si256(acx, climb_x), one), zero));
            const I cross_y = _mm256_and_si256(
                step_y,
                _mm256_cmpeq_epi64(_mm256_and_si256(_mm256_xor_si256(acy, climb_y), one), zero));
            climbing = _mm256_and_si256(
                _mm256_and_si256(climbing, _mm256_or_si256(cross_x, cross_y)),
                _mm256_and_si256(_mm256_cmpgt_epi64(alevel, _mm256_sub_epi64(p.top, one)),
                                 _mm256_cmpgt_epi64(root, alevel)));
            if (lanes_of(climbing) == 0) {
                break;
            }
            const I up_level = _mm256_add_epi64(alevel, one);
            const I px2 = _mm256_srli_epi64(acx, 1), py2 = _mm256_srli_epi64(acy, 1);
            const D parent = heights(p, up_level, px2, py2, climbing);
            climbing =
                _mm256_and_si256(climbing, as_mask(_mm256_cmp_pd(parent, empty, _CMP_EQ_OQ)));
            alevel = sel(climbing, up_level, alevel);
            acx = sel(climbing, px2, acx);
            acy = sel(climbing, py2, acy);
        }

        const int done = lanes_of(_mm256_or_si256(hit, miss));
        if (done != 0) {
            alignas(32) std::int64_t hit_lanes[kLanes];
            alignas(32) double h_lanes[kLanes], t_end_lanes[kLanes];
            store(hit_lanes, hit);
            _mm256_store_pd(h_lanes, h);
            _mm256_store_pd(t_end_lanes, t_end);
            for (int j = 0; j < kLanes; ++j) {
                if ((done & (1 << j)) == 0) {
                    continue;
                }
                const std::size_t i = s.ray[j];
                found[i] = hit_lanes[j] != 0 ? 1 : 0;
                if (hit_lanes[j] != 0) {
                    GridHit& g = hits[i];
                    g.x = s.cx[j];
                    g.y = s.cy[j];
                    g.t_in = s.t[j];
                    g.t_out = t_end_lanes[j];
                    g.entered_axis = static_cast<int>(s.entered[j]);
                    g.h = static_cast<float>(h_lanes[j]);
                    g.bottom = false;
                }
            }
        }
        store(s.cx, sel(below, dcx, acx));
        store(s.cy, sel(below, dcy, acy));
        store(s.level, sel(below, down_level, alevel));
        store(s.t, sel(below, t, t_out));
        store(s.entered, sel(below, load(s.entered), andnot(step_x, one)));
        if (done != 0) {
            for (int j = 0; j < kLanes; ++j) {
                if ((done & (1 << j)) == 0) {
                    continue;
                }
                if (next < count) {
                    s.start(j, rays[next], next, top);
                    ++next;
                } else {
                    s.stop(j);
                }
            }
        }
    }
}

}  // namespace

void trace_rays_avx2(const LevelTable& table, const GridRay* rays, std::size_t count, GridHit* hits,
                     std::uint8_t* found) {
    if (table.stacks() != 0) {
        throw std::logic_error("trace_rays_avx2: height stacks are traced by the scalar walk");
    }
    trace_avx2(table, rays, count, hits, found);
}

#else

bool avx2_available() {
    return false;
}

void trace_rays_avx2(const LevelTable&, const GridRay*, std::size_t, GridHit*, std::uint8_t*) {
    throw std::logic_error("trace_rays_avx2: not built for this CPU");
}

#endif

}  // namespace beamtrace::detail
