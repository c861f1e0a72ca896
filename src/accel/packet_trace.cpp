// Packets of coherent rays through one mesh's BVH (detail/packet_trace.hpp). This file must be
// compiled with -ffp-contract=off (cmake/BeamtraceModules.cmake): AVX-512 brings FMA, and a
// product fused into an FMA rounds once where the scalar test rounds twice.
#include "detail/packet_trace.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "core/simd_level.hpp"
#include "detail/queries.hpp"
#include "detail/walk_bvh.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define BEAMTRACE_PACKET_LANES 1
#else
#define BEAMTRACE_PACKET_LANES 0
#endif

#ifndef BEAMTRACE_FP_CONTRACT_OFF
// The scalar and packet tests must round every product; see the comment at the top.
#error "packet_trace.cpp must be compiled with -ffp-contract=off -DBEAMTRACE_FP_CONTRACT_OFF"
#endif

namespace beamtrace::detail {
namespace {

/// One ray as the BVH backend traces it alone (BvhTraverser with a NearestVisitor).
void trace_single(const Bvh& bvh, const TriangleMesh& mesh, const TraceRay& r, HitBatch& hits,
                  std::size_t i) {
    NearestVisitor vis(r);
    vis.enter(mesh, r, 0, false);
    walk_bvh(bvh, r, vis, [&](std::uint32_t face) { return vis.visit(face); });
    vis.store(hits, i);
}

#if BEAMTRACE_PACKET_LANES

// One copy of the kernel per instruction set, each compiled for it by function attributes only
// (as the height-field view's lanes are), so nothing shared with the rest of the program is
// built for an instruction set the CPU may lack.
namespace avx2 {
constexpr int kLanes = 8;
using vf = float __attribute__((vector_size(32)));
using vi = std::int32_t __attribute__((vector_size(32)));
using vu = std::uint32_t __attribute__((vector_size(32)));
#define BT_PK __attribute__((target("avx2"), always_inline)) inline
#define BT_PK_ENTRY __attribute__((target("avx2")))
BT_PK std::uint32_t lane_bits(vi m) {
    return static_cast<std::uint32_t>(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
}
/// All bits set in the lanes of `m` (a comparison's form of a lane mask).
BT_PK vi lanes_of(std::uint32_t m) {
    const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i b = _mm256_and_si256(_mm256_set1_epi32(static_cast<int>(m)), bit);
    return reinterpret_cast<vi>(_mm256_cmpeq_epi32(b, bit));
}
/// The greatest (least) lane of x, which holds no NaN.
BT_PK float lanes_max(vf x) {
    __m128 m = _mm_max_ps(_mm256_castps256_ps128(reinterpret_cast<__m256>(x)),
                          _mm256_extractf128_ps(reinterpret_cast<__m256>(x), 1));
    m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_max_ss(m, _mm_shuffle_ps(m, m, 1)));
}
BT_PK float lanes_min(vf x) {
    __m128 m = _mm_min_ps(_mm256_castps256_ps128(reinterpret_cast<__m256>(x)),
                          _mm256_extractf128_ps(reinterpret_cast<__m256>(x), 1));
    m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    return _mm_cvtss_f32(_mm_min_ss(m, _mm_shuffle_ps(m, m, 1)));
}
BT_PK vf lanes_sqrt(vf x) {
    return reinterpret_cast<vf>(_mm256_sqrt_ps(reinterpret_cast<__m256>(x)));
}
/// Eight doubles in float, four at a time: one vector of eight doubles copied from x went
/// through the stack (two 16-byte stores read back by one 32-byte load, which the store buffer
/// cannot forward: 13 % of the car's trace_range).
BT_PK vf lanes_to_float(const double* x) {
    const __m128 lo = _mm256_cvtpd_ps(_mm256_loadu_pd(x));
    const __m128 hi = _mm256_cvtpd_ps(_mm256_loadu_pd(x + 4));
    return reinterpret_cast<vf>(_mm256_set_m128(hi, lo));
}
#include "detail/packet_kernel.inl"
#undef BT_PK_ENTRY
#undef BT_PK
}  // namespace avx2

// GCC 12 warns of its own AVX-512 intrinsics' placeholder operands (GCC bug 105593).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
namespace avx512 {
constexpr int kLanes = 16;
using vf = float __attribute__((vector_size(64)));
using vi = std::int32_t __attribute__((vector_size(64)));
using vu = std::uint32_t __attribute__((vector_size(64)));
#define BT_PK __attribute__((target("avx512f,avx512dq,avx512cd,avx2"), always_inline)) inline
#define BT_PK_ENTRY __attribute__((target("avx512f,avx512dq,avx512cd,avx2")))
BT_PK std::uint32_t lane_bits(vi m) {
    return static_cast<std::uint32_t>(_mm512_movepi32_mask(reinterpret_cast<__m512i>(m)));
}
BT_PK vi lanes_of(std::uint32_t m) {
    return reinterpret_cast<vi>(_mm512_movm_epi32(static_cast<__mmask16>(m)));
}
/// The greatest (least) lane of x, which holds no NaN.
BT_PK float lanes_max(vf x) {
    return _mm512_reduce_max_ps(reinterpret_cast<__m512>(x));
}
BT_PK float lanes_min(vf x) {
    return _mm512_reduce_min_ps(reinterpret_cast<__m512>(x));
}
BT_PK vf lanes_sqrt(vf x) {
    return reinterpret_cast<vf>(_mm512_sqrt_ps(reinterpret_cast<__m512>(x)));
}
BT_PK vf lanes_to_float(const double* x) {
    using vd = double __attribute__((vector_size(kLanes * sizeof(double))));
    vd v;
    __builtin_memcpy(&v, x, sizeof v);
    return __builtin_convertvector(v, vf);
}
#include "detail/packet_kernel.inl"
#undef BT_PK_ENTRY
#undef BT_PK
}  // namespace avx512
#pragma GCC diagnostic pop

#endif

}  // namespace

int widest_packet_lanes() {
    if (!BEAMTRACE_PACKET_LANES) {
        return 1;
    }
    switch (cpu_simd_level()) {
        case SimdLevel::avx512:
            return 16;
        case SimdLevel::avx2:
            return 8;
        case SimdLevel::scalar:
            break;
    }
    return 1;
}

int packet_lanes(const BvhTraceConfig& config) {
    if (config.packets == BvhPackets::off) {
        return 1;
    }
    const int widest = widest_packet_lanes();
    if (config.lanes == 0) {
        return widest;
    }
    return (config.lanes == 8 || config.lanes == 16) && config.lanes <= widest ? config.lanes : 1;
}

void intersect_packets(const Bvh& bvh, const TriangleMesh& mesh, const RayBatch& rays,
                       std::size_t begin, std::size_t end, HitBatch& hits, int lanes,
                       bool only_coherent, double max_spread_rad) {
    const auto min_cos = static_cast<float>(std::cos(max_spread_rad));
#if BEAMTRACE_PACKET_LANES
    if (!bvh.nodes.empty()) {
        if (lanes == 16 && widest_packet_lanes() >= 16) {
            avx512::trace_range(bvh, mesh, rays, begin, end, hits, only_coherent, min_cos);
            return;
        }
        if (lanes == 8 && widest_packet_lanes() >= 8) {
            avx2::trace_range(bvh, mesh, rays, begin, end, hits, only_coherent, min_cos);
            return;
        }
    }
#else
    (void)lanes;
    (void)only_coherent;
    (void)min_cos;
#endif
    for (std::size_t i = begin; i < end; ++i) {
        trace_single(bvh, mesh, make_trace_ray(rays, i), hits, i);
    }
}

void intersect_beams(const Bvh& bvh, const TriangleMesh& mesh, const RayBatch& rays,
                     std::size_t begin, std::size_t end, std::size_t rays_per_beam, HitBatch& hits,
                     int lanes, bool only_coherent, double max_spread_rad) {
#if BEAMTRACE_PACKET_LANES
    if (!bvh.nodes.empty() && rays_per_beam >= 2) {
        const auto min_cos = static_cast<float>(std::cos(max_spread_rad));
        if (lanes == 16 && widest_packet_lanes() >= 16 &&
            rays_per_beam <= std::size_t{avx512::kWalkRays}) {
            avx512::trace_beams(bvh, mesh, rays, begin, end, rays_per_beam, hits, only_coherent,
                                min_cos);
            return;
        }
        if (lanes == 8 && widest_packet_lanes() >= 8 &&
            rays_per_beam <= std::size_t{avx2::kWalkRays}) {
            avx2::trace_beams(bvh, mesh, rays, begin, end, rays_per_beam, hits, only_coherent,
                              min_cos);
            return;
        }
    }
#endif
    (void)rays_per_beam;
    intersect_packets(bvh, mesh, rays, begin, end, hits, lanes, only_coherent, max_spread_rad);
}

}  // namespace beamtrace::detail

namespace beamtrace {

int bvh_packet_lanes(const BvhTraceConfig& config) {
    return detail::packet_lanes(config);
}

}  // namespace beamtrace
