// The sampled Gaussians of a waveform (waveform.cpp) and their AVX2 and AVX-512 kernels
// (physics' private helpers).
#pragma once

#include <cstddef>
#include <cstdint>

namespace beamtrace::detail {

/// amplitude * exp(-(t - t0)^2 / (2 sigma^2)) on the bins [b0, b0 + n), by recurrence (three
/// exps, fast_exp's, detail/fast_exp.hpp): g is the first sample; the ratio of consecutive samples
/// is exp(-k (2 dt h + h^2)), itself scaled by `step` = exp(-2 k h^2) per bin.
/// No default member initialisers: arrays of them are not zeroed first (GaussianRun{} is all 0).
struct GaussianRun {
    double g, ratio, step;
    std::int64_t b0;
    std::size_t n;
};

/// Runs in the lanes of one AVX-512 register (of two AVX2 ones): one call of
/// add_runs_lanes_avx512 adds this many at most.
inline constexpr std::size_t kRunLanes = 8;

/// Runs added together by one call of add_runs_lanes, at most: AVX-512 adds them kRunLanes a
/// pass over the bins, AVX2 up to twenty a pass (in five registers).
inline constexpr std::size_t kRunsPerCall = 4 * kRunLanes;

/// The paths of add_runs_lanes: eight runs to an AVX-512 register, or four to an AVX2 one.
enum class RunLanes { avx2, avx512 };

/// True when the CPU runs add_runs_lanes by `path` (AVX2 or AVX-512F; neither under
/// ThreadSanitizer's build), or by some path (no argument).
[[nodiscard]] bool run_lanes_available(RunLanes path);
[[nodiscard]] bool run_lanes_available();

/// Adds runs[0, count) (count <= kRunsPerCall, each inside the bins [first, first + width)) to
/// y[0, width), bin b at y[b - first]: every bin receives the runs' samples in the order of
/// the runs, each sample the product of its run's recurrence alone, so every bin ends as one
/// run after the other added by recurrence would leave it, bit for bit, on either path (a run
/// adds nothing outside its bins; +0, which leaves a bin as it is: bins are never -0). By the
/// widest path this CPU runs (needs run_lanes_available()), or by `path` (needs
/// run_lanes_available(path)).
void add_runs_lanes(double* y, std::size_t width, std::int64_t first, const GaussianRun* runs,
                    std::size_t count);
void add_runs_lanes(RunLanes path, double* y, std::size_t width, std::int64_t first,
                    const GaussianRun* runs, std::size_t count);

/// The paths' kernels (gaussian_runs_avx2.cpp, gaussian_runs_avx512.cpp) and whether they run.
[[nodiscard]] bool run_lanes_avx2_available();
[[nodiscard]] bool run_lanes_avx512_available();
/// add_runs_lanes_avx2 takes count <= kRunsPerCall; add_runs_lanes_avx512 count <= kRunLanes.
void add_runs_lanes_avx2(double* y, std::size_t width, std::int64_t first, const GaussianRun* runs,
                         std::size_t count);
void add_runs_lanes_avx512(double* y, std::size_t width, std::int64_t first,
                           const GaussianRun* runs, std::size_t count);

}  // namespace beamtrace::detail
