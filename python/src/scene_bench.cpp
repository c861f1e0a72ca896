// Scene._intersect_seconds: the C++ side of bench/python/trace_rate.py, the backend's own rate on
// the rays of a trace call, timed in C++ as `beamtrace bench` times "our" backends.
#include <algorithm>
#include <chrono>
#include <cstddef>
#include <ctime>
#include <limits>
#include <string>

#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "py_scene.hpp"
#include "rays.hpp"

namespace beamtrace::python {
namespace {

/// Seconds of CPU time this process has used (every thread, user and system).
double process_cpu_seconds() {
    timespec ts{};
    (void)clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// (best seconds of `repeats` calls of Backend::intersect on all the rays, hits of the last, CPU
/// seconds of the process during the best call). The rays are converted, the pool started and
/// the backend built before the clock runs; the hit batch is allocated and filled once, before
/// (as bench/harness/throughput_bench.cpp does): the calls write into memory already touched.
py::tuple intersect_seconds(PyScene& self, const py::handle& origins, const py::handle& directions,
                            const std::string& backend, unsigned threads, unsigned repeats) {
    const BackendKind kind = parse_backend_kind(backend);
    ThreadPool pool(threads);
    const RayBatch rays =
        make_rays(origins, directions, std::numeric_limits<double>::infinity(), pool);
    double best = std::numeric_limits<double>::infinity();
    double best_cpu = 0.0;
    std::size_t hit_count = 0;
    {
        py::gil_scoped_release release;
        const Backend& b = self.backend(kind, pool);
        HitBatch hits;
        hits.resize(rays.size());
        for (unsigned r = 0; r < std::max(repeats, 1u); ++r) {
            const double cpu_start = process_cpu_seconds();
            const auto start = std::chrono::steady_clock::now();
            b.intersect(rays, 0, rays.size(), hits, pool);
            const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
            if (took.count() < best) {
                best = took.count();
                best_cpu = process_cpu_seconds() - cpu_start;
            }
        }
        hit_count = static_cast<std::size_t>(
            std::count_if(hits.face.begin(), hits.face.end(), [](auto f) { return f != kNoFace; }));
    }
    return py::make_tuple(best, hit_count, best_cpu);
}

}  // namespace

void bind_scene_bench(py::class_<PyScene>& scene) {
    scene.def(
        "_intersect_seconds", &intersect_seconds, py::arg("origins"), py::arg("directions"),
        py::arg("backend") = "bvh", py::arg("threads") = 0u, py::arg("repeats") = 3u,
        "Benchmarks only (bench/python/trace_rate.py): (best seconds of `repeats` calls of "
        "the backend's own intersect on these rays, timed in C++; rays that hit; the process's "
        "CPU seconds during that call).");
}

}  // namespace beamtrace::python
