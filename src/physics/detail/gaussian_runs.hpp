// The sampled Gaussians of a waveform (waveform.cpp) and their AVX-512 kernel (physics' private
// helpers).
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

/// Runs added together by one call of add_runs_lanes, at most.
inline constexpr std::size_t kRunLanes = 8;

/// True when the CPU runs add_runs_lanes (AVX-512F; not under ThreadSanitizer's build).
[[nodiscard]] bool run_lanes_available();

/// Adds runs[0, count) (count <= kRunLanes, each inside the bins [first, first + width)) to
/// y[0, width), bin b at y[b - first]: every bin receives the runs' samples in the order of
/// the runs, each sample the product of its run's recurrence alone, so every bin ends as one
/// run after the other added by recurrence would leave it, bit for bit (a run adds nothing
/// outside its bins; +0, which leaves a bin as it is: bins are never -0). Needs
/// run_lanes_available().
void add_runs_lanes(double* y, std::size_t width, std::int64_t first, const GaussianRun* runs,
                    std::size_t count);

}  // namespace beamtrace::detail
