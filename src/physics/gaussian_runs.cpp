#include "physics/detail/gaussian_runs.hpp"

#include <algorithm>

namespace beamtrace::detail {

bool run_lanes_available(RunLanes path) {
    return path == RunLanes::avx512 ? run_lanes_avx512_available() : run_lanes_avx2_available();
}

bool run_lanes_available() {
    return run_lanes_avx512_available() || run_lanes_avx2_available();
}

void add_runs_lanes(RunLanes path, double* y, std::size_t width, std::int64_t first,
                    const GaussianRun* runs, std::size_t count) {
    if (path == RunLanes::avx512) {  // kRunLanes to a register: one pass per eight runs
        for (std::size_t from = 0; from < count; from += kRunLanes) {
            add_runs_lanes_avx512(y, width, first, runs + from, std::min(kRunLanes, count - from));
        }
    } else {
        add_runs_lanes_avx2(y, width, first, runs, count);
    }
}

void add_runs_lanes(double* y, std::size_t width, std::int64_t first, const GaussianRun* runs,
                    std::size_t count) {
    add_runs_lanes(run_lanes_avx512_available() ? RunLanes::avx512 : RunLanes::avx2, y, width,
                   first, runs, count);
}

}  // namespace beamtrace::detail
