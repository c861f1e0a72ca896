#include "rays.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <string>

#include "numpy_arrays.hpp"

namespace beamtrace::python {
namespace {

bool finite(const Vec3d& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// What is wrong with a row, in the order the rows are checked (0: nothing).
enum class RowProblem { none, origin, direction, zero, too_long };

RowProblem row_problem(const Vec3d& org, const Vec3d& dir, double len) {
    if (!finite(org)) {
        return RowProblem::origin;
    }
    if (!finite(dir)) {
        return RowProblem::direction;
    }
    if (!(len > 0.0)) {
        return RowProblem::zero;
    }
    return std::isfinite(len) ? RowProblem::none : RowProblem::too_long;
}

[[noreturn]] void bad_row(std::size_t row, RowProblem problem) {
    const char* name = problem == RowProblem::origin ? "origins" : "directions";
    const char* what = problem == RowProblem::origin || problem == RowProblem::direction
                           ? "is not finite"
                       : problem == RowProblem::zero ? "has zero length"
                                                     : "is too long to normalise";
    throw py::value_error(std::string(name) + ": row " + std::to_string(row) + " " + what);
}

// Rows per block: a batch up to this size is converted on the calling thread (waking the pool
// costs more than it saves).
constexpr std::size_t kGrain = 65536;

}  // namespace

RayBatch make_rays(const py::handle& origins, const py::handle& directions, double max_range_m,
                   ThreadPool& pool) {
    const CArray<double> o = vec3_array(origins, "origins");
    const CArray<double> d = vec3_array(directions, "directions");
    if (o.shape(0) != d.shape(0)) {
        throw py::value_error("directions: " + std::to_string(d.shape(0)) +
                              " rows, but origins has " + std::to_string(o.shape(0)));
    }
    if (!(max_range_m > 0.0)) {
        throw py::value_error("max_range_m: " + std::to_string(max_range_m) +
                              ", expected a positive range (inf: no limit)");
    }
    const auto n = static_cast<std::size_t>(o.shape(0));
    const double* op = o.data();  // C-contiguous (n, 3): o and d keep them alive
    const double* dp = d.data();
    RayBatch rays;
    std::atomic<std::size_t> first_bad{n};
    {
        // Plain memory from here on: the rows are read and the batch filled on every thread.
        py::gil_scoped_release release;
        rays.resize(n);
        pool.parallel_for(n, kGrain, [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) {
                const Vec3d org{op[3 * i], op[3 * i + 1], op[3 * i + 2]};
                const Vec3d dir{dp[3 * i], dp[3 * i + 1], dp[3 * i + 2]};
                const double len = length(dir);
                const RowProblem p = row_problem(org, dir, len);
                if (p != RowProblem::none) [[unlikely]] {
                    // The lowest bad row wins, whichever thread finds it first.
                    std::size_t seen = first_bad.load();
                    while (i < seen && !first_bad.compare_exchange_weak(seen, i)) {
                    }
                    return;  // the rest of this chunk cannot hold a lower row
                }
                rays.set(i, org, dir * (1.0 / len), 0.0, max_range_m);
            }
        });
    }
    if (first_bad.load() < n) {
        // The lowest bad row; its problem, found again.
        const std::size_t i = first_bad.load();
        const Vec3d org{op[3 * i], op[3 * i + 1], op[3 * i + 2]};
        const Vec3d dir{dp[3 * i], dp[3 * i + 1], dp[3 * i + 2]};
        bad_row(i, row_problem(org, dir, length(dir)));
    }
    return rays;
}

}  // namespace beamtrace::python
