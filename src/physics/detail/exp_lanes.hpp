// std::exp of many arguments at once, bit for bit the C library's (physics' private helper).
#pragma once

#include <cstddef>

namespace beamtrace::detail {

/// out[i] = std::exp(x[i]) for i < n, bit for bit (out may be x). Four lanes at a time with
/// AVX2 and FMA where the CPU has them and the C library's exp is the one the lanes replicate
/// (glibc's, since 2.28: a 128-entry table and a degree-5 polynomial, its FMA variant; checked
/// once per process against std::exp, else every element calls std::exp). Arguments outside
/// that exp's fast range (|x| below 2^-54 or from 512 on, NaN) call std::exp as well.
void exp_lanes(const double* x, double* out, std::size_t n);

/// True when exp_lanes runs its lanes on this machine (false: it calls std::exp throughout).
[[nodiscard]] bool exp_lanes_vectorised();

}  // namespace beamtrace::detail
