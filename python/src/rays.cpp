#include "rays.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <string>

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

// Rows per block: a batch up to this size is converted on the calling thread (waking the pool
// costs more than it saves).
constexpr std::size_t kGrain = 65536;

}  // namespace

RayRows::RayRows(const py::handle& origins, const py::handle& directions, double max_range_m)
    : o_(vec3_array(origins, "origins")),
      d_(vec3_array(directions, "directions")),
      max_range_m_(max_range_m) {
    if (o_.shape(0) != d_.shape(0)) {
        throw py::value_error("directions: " + std::to_string(d_.shape(0)) +
                              " rows, but origins has " + std::to_string(o_.shape(0)));
    }
    if (!(max_range_m > 0.0)) {
        throw py::value_error("max_range_m: " + std::to_string(max_range_m) +
                              ", expected a positive range (inf: no limit)");
    }
    n_ = static_cast<std::size_t>(o_.shape(0));
    op_ = o_.data();  // C-contiguous (n, 3): o_ and d_ keep them alive
    dp_ = d_.data();
}

std::size_t RayRows::convert(std::size_t begin, std::size_t end, RayBatch& out,
                             std::size_t at) const {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3d org{op_[3 * i], op_[3 * i + 1], op_[3 * i + 2]};
        const Vec3d dir{dp_[3 * i], dp_[3 * i + 1], dp_[3 * i + 2]};
        const double len = length(dir);
        if (row_problem(org, dir, len) != RowProblem::none) [[unlikely]] {
            return i;
        }
        out.set(at + (i - begin), org, dir * (1.0 / len), 0.0, max_range_m_);
    }
    return n_;
}

void RayRows::raise_bad_row(std::size_t row) const {
    const Vec3d org{op_[3 * row], op_[3 * row + 1], op_[3 * row + 2]};
    const Vec3d dir{dp_[3 * row], dp_[3 * row + 1], dp_[3 * row + 2]};
    const RowProblem problem = row_problem(org, dir, length(dir));
    const char* name = problem == RowProblem::origin ? "origins" : "directions";
    const char* what = problem == RowProblem::origin || problem == RowProblem::direction
                           ? "is not finite"
                       : problem == RowProblem::zero ? "has zero length"
                                                     : "is too long to normalise";
    throw py::value_error(std::string(name) + ": row " + std::to_string(row) + " " + what);
}

RayBatch make_rays(const py::handle& origins, const py::handle& directions, double max_range_m,
                   ThreadPool& pool) {
    const RayRows rows(origins, directions, max_range_m);
    const std::size_t n = rows.size();
    RayBatch rays;
    std::atomic<std::size_t> first_bad{n};
    {
        // Plain memory from here on: the rows are read and the batch filled on every thread.
        py::gil_scoped_release release;
        rays.resize(n);
        pool.parallel_for(n, kGrain, [&](std::size_t begin, std::size_t end) {
            const std::size_t bad = rows.convert(begin, end, rays, begin);
            // The lowest bad row wins, whichever thread finds it first (the rest of a chunk
            // cannot hold a lower one).
            std::size_t seen = first_bad.load();
            while (bad < seen && !first_bad.compare_exchange_weak(seen, bad)) {
            }
        });
    }
    if (first_bad.load() < n) {
        rows.raise_bad_row(first_bad.load());
    }
    return rays;
}

}  // namespace beamtrace::python
