// Rays from Python: origins and directions as (N, 3) arrays, checked and converted into RayBatch
// rows (directions normalised), all at once (make_rays) or block by block (RayRows::convert).
#pragma once

#include <cstddef>

#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "bindings.hpp"
#include "numpy_arrays.hpp"

namespace beamtrace::python {

/// The rows of a query's (N, 3) origins and directions, checked for shape and dtype (and
/// converted to C-contiguous float64 if they are not), kept alive while they are read.
class RayRows {
  public:
    /// Raises ValueError naming the argument for a wrong shape or dtype, row counts that
    /// differ, or a max_range_m that is not positive.
    RayRows(const py::handle& origins, const py::handle& directions, double max_range_m);

    [[nodiscard]] std::size_t size() const { return n_; }
    /// Sets rays at..at + (end - begin) of `out` (which must hold them) to rows [begin, end):
    /// origins[i] + t * directions[i] / |directions[i]|, t in [0, max_range_m]. Returns the
    /// first row of them whose origin or direction is NaN or infinite or whose direction has
    /// zero length (the rays from it on are not set), or size() when all are good. Touches no
    /// Python object: call it with the GIL released, on any thread.
    std::size_t convert(std::size_t begin, std::size_t end, RayBatch& out, std::size_t at) const;
    /// Raises ValueError naming the argument and what is wrong with `row` (a row convert()
    /// returned).
    [[noreturn]] void raise_bad_row(std::size_t row) const;

  private:
    CArray<double> o_, d_;
    const double* op_ = nullptr;
    const double* dp_ = nullptr;
    std::size_t n_ = 0;
    double max_range_m_;
};

/// All the rows of `origins` and `directions` as one batch (RayRows's checks, then every row's:
/// ValueError for the lowest bad row). The rows are converted on the threads of `pool`, the GIL
/// released.
[[nodiscard]] RayBatch make_rays(const py::handle& origins, const py::handle& directions,
                                 double max_range_m, ThreadPool& pool);

}  // namespace beamtrace::python
