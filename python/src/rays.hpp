// Rays from Python: origins and directions as (N, 3) arrays, checked and copied into a RayBatch.
#pragma once

#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "bindings.hpp"

namespace beamtrace::python {

/// The rays origins[i] + t * directions[i] / |directions[i]|, t in [0, max_range_m]: directions
/// are normalised, so ranges are metres. Raises ValueError naming the argument for a wrong shape
/// or dtype, a coordinate that is NaN or infinite (the lowest such row), a zero-length direction,
/// row counts that differ, or a max_range_m that is not positive. The rows are converted on the
/// threads of `pool`, the GIL released.
[[nodiscard]] RayBatch make_rays(const py::handle& origins, const py::handle& directions,
                                 double max_range_m, ThreadPool& pool);

}  // namespace beamtrace::python
