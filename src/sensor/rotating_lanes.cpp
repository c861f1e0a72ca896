#include "sensor/detail/rotating_lanes.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include "sensor/detail/index_quad.hpp"
#define BEAMTRACE_ROTATING_LANES_AVX2 1
#endif

namespace beamtrace::detail {

#if BEAMTRACE_ROTATING_LANES_AVX2
namespace {

/// The azimuths of beams b .. b + 3 wrapped into [-180, 180) as wrap_deg() does where w = deg
/// + 180 lies in [0, 720); false where a lane needs fmod.
__attribute__((target("avx2"))) inline bool azimuth_quad(const FiringParams& f, std::size_t b,
                                                         __m256d& az) {
    const __m256d head =
        _mm256_add_pd(_mm256_set1_pd(f.head_deg), _mm256_loadu_pd(f.within_deg + b));
    const __m256d deg = _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(f.start_azimuth_deg),
                                                    _mm256_mul_pd(_mm256_set1_pd(f.sign), head)),
                                      _mm256_loadu_pd(f.offset_deg + b));
    const __m256d w = _mm256_add_pd(deg, _mm256_set1_pd(180.0));
    const __m256d turn = _mm256_set1_pd(360.0);
    const __m256d past = _mm256_cmp_pd(w, turn, _CMP_GE_OQ);
    const __m256d in_range = _mm256_and_pd(_mm256_cmp_pd(w, _mm256_setzero_pd(), _CMP_GE_OQ),
                                           _mm256_cmp_pd(w, _mm256_set1_pd(720.0), _CMP_LT_OQ));
    if (_mm256_movemask_pd(in_range) != 15) {
        return false;
    }
    az = _mm256_sub_pd(_mm256_sub_pd(w, _mm256_and_pd(past, turn)), _mm256_set1_pd(180.0));
    return true;
}

/// firing_lanes() where the CPU has AVX2.
__attribute__((target("avx2"))) std::size_t firing_quads(const FiringParams& f, std::uint64_t first,
                                                         std::size_t b, std::size_t count,
                                                         PulseBatch& out, std::size_t j) {
    const __m256d cos_head = _mm256_set1_pd(f.cos_head), sin_head = _mm256_set1_pd(f.sin_head);
    const __m256d start = _mm256_set1_pd(f.start_s), rate = _mm256_set1_pd(f.pulse_rate_hz);
    std::size_t done = 0;
    for (; done + 4 <= count; done += 4) {
        const std::size_t beam = b + done, slot = j + done;
        __m256d az;
        if (!azimuth_quad(f, beam, az)) {
            break;
        }
        const __m256d cb = _mm256_loadu_pd(f.cos_beam + beam);
        const __m256d sb = _mm256_loadu_pd(f.sin_beam + beam);
        const __m256d cos_az =
            _mm256_sub_pd(_mm256_mul_pd(cos_head, cb), _mm256_mul_pd(sin_head, sb));
        const __m256d sin_az =
            _mm256_add_pd(_mm256_mul_pd(sin_head, cb), _mm256_mul_pd(cos_head, sb));
        const __m256d ce = _mm256_loadu_pd(f.cos_elevation + beam);
        alignas(32) double x[4], y[4], z[4];
        _mm256_store_pd(x, _mm256_mul_pd(ce, cos_az));
        _mm256_store_pd(y, _mm256_mul_pd(ce, sin_az));
        _mm256_store_pd(z, _mm256_loadu_pd(f.sin_elevation + beam));
        for (std::size_t l = 0; l < 4; ++l) {
            Vec3d& d = out.direction[slot + l];
            d.x = x[l];
            d.y = y[l];
            d.z = z[l];
            out.channel[slot + l] =
                f.channels == nullptr ? static_cast<std::uint16_t>(beam + l) : f.channels[beam + l];
        }
        _mm256_storeu_pd(out.time_s.data() + slot,
                         _mm256_add_pd(start, _mm256_div_pd(index_quad(first + done), rate)));
        _mm_storeu_ps(out.scan_angle_deg.data() + slot, _mm256_cvtpd_ps(az));
    }
    return done;
}

}  // namespace
#endif

std::size_t firing_lanes(const FiringParams& f, std::uint64_t first, std::size_t b,
                         std::size_t count, PulseBatch& out, std::size_t j) {
#if BEAMTRACE_ROTATING_LANES_AVX2
    if (count < 4 || !__builtin_cpu_supports("avx2") || first >= kExactIndices ||
        count >= kExactIndices - first) {
        return 0;
    }
    return firing_quads(f, first, b, count, out, j);
#else
    (void)f, (void)first, (void)b, (void)count, (void)out, (void)j;
    return 0;
#endif
}

}  // namespace beamtrace::detail
