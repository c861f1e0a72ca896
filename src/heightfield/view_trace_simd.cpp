#include "detail/view_trace_simd.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define BEAMTRACE_VIEW_LANES 1
#else
#define BEAMTRACE_VIEW_LANES 0
#endif

#include "core/simd_level.hpp"

namespace beamtrace::detail {

#if BEAMTRACE_VIEW_LANES

// One copy of the lane kernel per instruction set, each in its own namespace and compiled for
// its instruction set by function attributes only, so that nothing shared with the rest of the
// program is built for an instruction set the CPU may lack.
namespace {
namespace avx2 {
#define BT_LANES __attribute__((target("avx2"), always_inline)) inline
#include "detail/view_lanes_avx2.inl"
#undef BT_LANES
#define BT_LANES __attribute__((target("avx2")))
#define BT_LANES_INLINE __attribute__((target("avx2"), always_inline)) inline
#include "detail/view_lanes_setup.inl"
#include "detail/view_lanes_shade.inl"
#undef BT_LANES_INLINE
#undef BT_LANES
}  // namespace avx2

// The walk for AVX2 CPUs: eight rays, two registers a value (view_lanes_avx2x2.inl).
namespace avx2x2 {
#define BT_LANES __attribute__((target("avx2"), always_inline)) inline
namespace one {
#include "detail/view_lanes_avx2.inl"
}  // namespace one
#include "detail/view_lanes_avx2x2.inl"
#undef BT_LANES
#define BT_LANES __attribute__((target("avx2")))
#define BT_LANES_INLINE __attribute__((target("avx2"), always_inline)) inline
#include "detail/view_lanes_kernel.inl"
#undef BT_LANES_INLINE
#undef BT_LANES
}  // namespace avx2x2

// GCC 12 warns of its own AVX-512 intrinsics' placeholder operands (GCC bug 105593).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
namespace avx512 {
#define BT_LANES __attribute__((target("avx512f,avx512dq,avx512cd,avx2"), always_inline)) inline
#include "detail/view_lanes_avx512.inl"
#undef BT_LANES
#define BT_LANES __attribute__((target("avx512f,avx512dq,avx512cd,avx2")))
#define BT_LANES_INLINE \
    __attribute__((target("avx512f,avx512dq,avx512cd,avx2"), always_inline)) inline
#include "detail/view_lanes_kernel.inl"
#include "detail/view_lanes_setup.inl"
#include "detail/view_lanes_shade.inl"
#undef BT_LANES_INLINE
#undef BT_LANES
}  // namespace avx512
#pragma GCC diagnostic pop
}  // namespace

int widest_lanes() {
    switch (cpu_simd_level()) {
        case SimdLevel::avx512:
            return 8;
        case SimdLevel::avx2:
            return 4;
        case SimdLevel::scalar:
            break;
    }
    return 1;
}

int trace_rays_lanes(int lanes, const LevelTable& table, const GridRay* rays, std::size_t count,
                     GridHit* hits, std::uint8_t* found) {
    if (table.stacks() != 0) {
        throw std::logic_error("trace_rays_lanes: height stacks are traced one ray at a time");
    }
    if (lanes == 8 && widest_lanes() >= 8) {
        avx512::trace(table, rays, count, hits, found);
        return 8;
    }
    if (lanes == 4 && widest_lanes() >= 4) {
        avx2x2::trace(table, rays, count, hits, found);
        return 4;
    }
    throw std::logic_error("trace_rays_lanes: " + std::to_string(lanes) +
                           " lanes are not available on this CPU");
}

void ray_setup_lanes(int lanes, const DirectionFrame& frame, const ClipFrame& clip, const double* u,
                     double v, int count, RowDirections& out) {
    if (lanes == 8 && widest_lanes() >= 8) {
        avx512::directions(frame, clip, u, v, count, out);
        return;
    }
    if (lanes == 4 && widest_lanes() >= 4) {
        avx2::directions(frame, clip, u, v, count, out);
        return;
    }
    throw std::logic_error("ray_setup_lanes: " + std::to_string(lanes) +
                           " lanes are not available on this CPU");
}

int start_rays_lanes(int lanes, const ClipFrame& clip, double t, std::int64_t cells,
                     RowDirections& rows) {
    if (lanes == 8 && widest_lanes() >= 8) {
        return avx512::start_rays(clip, t, cells, rows);
    }
    if (lanes == 4 && widest_lanes() >= 4) {
        return avx2::start_rays(clip, t, cells, rows);
    }
    throw std::logic_error("start_rays_lanes: " + std::to_string(lanes) +
                           " lanes are not available on this CPU");
}

void shade_lanes(int lanes, const ShadeFrame& frame, ShadeBatch& batch, int count) {
    if (lanes == 8 && widest_lanes() >= 8) {
        avx512::shade(frame, batch, count);
        return;
    }
    if (lanes == 4 && widest_lanes() >= 4) {
        avx2::shade(frame, batch, count);
        return;
    }
    throw std::logic_error("shade_lanes: " + std::to_string(lanes) +
                           " lanes are not available on this CPU");
}

#else

int widest_lanes() {
    return 1;
}

int trace_rays_lanes(int lanes, const LevelTable&, const GridRay*, std::size_t, GridHit*,
                     std::uint8_t*) {
    throw std::logic_error("trace_rays_lanes: " + std::to_string(lanes) +
                           " lanes are not built for this CPU");
}

void ray_setup_lanes(int lanes, const DirectionFrame&, const ClipFrame&, const double*, double, int,
                     RowDirections&) {
    throw std::logic_error("ray_setup_lanes: " + std::to_string(lanes) +
                           " lanes are not built for this CPU");
}

int start_rays_lanes(int lanes, const ClipFrame&, double, std::int64_t, RowDirections&) {
    throw std::logic_error("start_rays_lanes: " + std::to_string(lanes) +
                           " lanes are not built for this CPU");
}

void shade_lanes(int lanes, const ShadeFrame&, ShadeBatch&, int) {
    throw std::logic_error("shade_lanes: " + std::to_string(lanes) +
                           " lanes are not built for this CPU");
}

#endif

}  // namespace beamtrace::detail
