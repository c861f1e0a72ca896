// Four consecutive pulse indices as doubles in AVX2 lanes: the scan patterns' lane paths
// (line_angles.cpp, rotating_lanes.cpp) compute a pulse's time as start + i / rate from them.
#pragma once

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include <cstdint>

namespace beamtrace::detail {

/// Indices i .. i + 3 as doubles, exact below 2^52: the bits of 2^52 + i read as a double, less
/// 2^52 (what static_cast<double>(i) gives there).
__attribute__((target("avx2"))) inline __m256d index_quad(std::uint64_t i) {
    const __m256i lanes = _mm256_add_epi64(_mm256_set1_epi64x(static_cast<long long>(i)),
                                           _mm256_set_epi64x(3, 2, 1, 0));
    const __m256d two52 = _mm256_set1_pd(4503599627370496.0);
    return _mm256_sub_pd(_mm256_or_pd(_mm256_castsi256_pd(lanes), two52), two52);
}

/// The indices below which index_quad() is exact.
inline constexpr std::uint64_t kExactIndices = std::uint64_t{1} << 52;

}  // namespace beamtrace::detail
#endif
