// The widest SIMD instruction set this CPU runs, for the kernels compiled once per instruction
// set by function attributes (the BVH's ray packets, the height-field view's lanes).
#pragma once

namespace beamtrace::detail {

enum class SimdLevel { scalar, avx2, avx512 };

/// AVX-512 counts when the CPU has F, DQ and CD (what the kernels' target attributes name).
/// Asked once per process; scalar on CPUs and compilers without the x86 builtins.
[[nodiscard]] inline SimdLevel cpu_simd_level() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const SimdLevel level = [] {
        __builtin_cpu_init();
        if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
            __builtin_cpu_supports("avx512cd")) {
            return SimdLevel::avx512;
        }
        return __builtin_cpu_supports("avx2") ? SimdLevel::avx2 : SimdLevel::scalar;
    }();
    return level;
#else
    return SimdLevel::scalar;
#endif
}

}  // namespace beamtrace::detail
