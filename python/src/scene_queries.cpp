// Scene.trace (nearest hits as NumPy arrays) and Scene.occluded, the GIL released while tracing.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "numpy_arrays.hpp"
#include "py_scene.hpp"
#include "rays.hpp"

namespace beamtrace::python {
namespace {

/// Nearest hits as NumPy arrays, one row per ray (a miss: range inf, face/part/label -1, u = v =
/// 0, normal 0).
struct Hits {
    py::array range_m, face, part, label, u, v, normal;
};

// The per-ray results before they become arrays (filled with the GIL released).
struct TraceOutput {
    HitBatch hits;
    OutputVector<std::int64_t> face, part, label;  // written ray by ray: no zero fill first
    OutputVector<double> normal;                   ///< 3 per ray
};

// Face, part, label and normal of the hits of rays [begin, end) (a miss: -1, normal 0).
void describe_hits(const Scene& scene, const RayBatch& rays, TraceOutput& out, std::size_t begin,
                   std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        if (!out.hits.hit(i)) {
            out.face[i] = out.part[i] = out.label[i] = -1;
            out.normal[3 * i] = out.normal[3 * i + 1] = out.normal[3 * i + 2] = 0.0;
            continue;
        }
        const std::uint32_t f = out.hits.face[i];
        const std::size_t p = scene.part_of_face(f);
        const Vec3d at = rays.origin(i) + rays.direction(i) * static_cast<double>(out.hits.t[i]);
        const Vec3d nrm = scene.geometry.normal_at(f, at);
        out.face[i] = f;
        out.part[i] = static_cast<std::int64_t>(p);
        out.label[i] = scene.parts[p].label;
        out.normal[3 * i] = nrm.x;
        out.normal[3 * i + 1] = nrm.y;
        out.normal[3 * i + 2] = nrm.z;
    }
}

// Nearest hits and what they hit. Each block of the backend's preferred size is traced and then
// described on one thread, while the faces its rays met are still in the cache: describing all
// rays after tracing them all read the faces from memory again, which cost 10 % of the rate on
// the 1.48 M-triangle DEM (bench/python/trace_rate.py).
void trace_and_describe(const Scene& scene, const Backend& b, const RayBatch& rays,
                        TraceOutput& out, ThreadPool& pool) {
    const std::size_t n = rays.size();
    out.hits.resize(n);
    out.face.resize(n);
    out.part.resize(n);
    out.label.resize(n);
    out.normal.resize(3 * n);
    pool.parallel_for(n, b.traits().preferred_batch_rays, [&](std::size_t begin, std::size_t end) {
        ThreadPool serial(1);  // no workers: this thread traces the block
        b.intersect(rays, begin, end, out.hits, serial);
        describe_hits(scene, rays, out, begin, end);
    });
}

Hits to_hits(TraceOutput&& out) {
    const auto n = static_cast<py::ssize_t>(out.face.size());
    Hits h;
    h.range_m = to_numpy(std::move(out.hits.t), {n});
    h.u = to_numpy(std::move(out.hits.u), {n});
    h.v = to_numpy(std::move(out.hits.v), {n});
    h.face = to_numpy(std::move(out.face), {n});
    h.part = to_numpy(std::move(out.part), {n});
    h.label = to_numpy(std::move(out.label), {n});
    h.normal = to_numpy(std::move(out.normal), {n, 3});
    return h;
}

Hits trace(PyScene& self, const py::handle& origins, const py::handle& directions,
           const std::string& backend, unsigned threads, double max_range_m) {
    const BackendKind kind = parse_backend_kind(backend);
    ThreadPool pool(threads);
    const RayBatch rays = make_rays(origins, directions, max_range_m, pool);
    TraceOutput out;
    {
        py::gil_scoped_release release;
        trace_and_describe(self.scene(), self.backend(kind, pool), rays, out, pool);
    }
    return to_hits(std::move(out));
}

py::array occluded(PyScene& self, const py::handle& origins, const py::handle& directions,
                   const std::string& backend, unsigned threads, double max_range_m) {
    const BackendKind kind = parse_backend_kind(backend);
    ThreadPool pool(threads);
    const RayBatch rays = make_rays(origins, directions, max_range_m, pool);
    std::vector<std::uint8_t> blocked(rays.size(), 0);
    {
        py::gil_scoped_release release;
        self.backend(kind, pool).occluded(rays, 0, rays.size(), blocked, pool);
    }
    // One byte per ray, 0 or 1: NumPy's bool layout.
    return to_numpy(std::move(blocked), {static_cast<py::ssize_t>(rays.size())})
        .attr("view")(py::dtype::of<bool>());
}

}  // namespace

void bind_scene_queries(py::module_& m, py::class_<PyScene>& scene) {
    py::class_<Hits>(m, "Hits", "Nearest hits of Scene.trace, one row per ray")
        .def_readonly("range_m", &Hits::range_m, "float32 (N,): metres, inf for a miss")
        .def_readonly("face", &Hits::face, "int64 (N,): face ID, -1 for a miss")
        .def_readonly("part", &Hits::part, "int64 (N,): index into Scene.parts, -1 for a miss")
        .def_readonly("label", &Hits::label, "int64 (N,): the part's class, -1 for a miss")
        .def_readonly("u", &Hits::u, "float32 (N,): barycentric of the face's V1 (0 for a miss)")
        .def_readonly("v", &Hits::v, "float32 (N,): barycentric of the face's V2 (0 for a miss)")
        .def_readonly("normal", &Hits::normal, "float64 (N, 3): unit normal, 0 for a miss")
        .def("__len__", [](const Hits& h) { return h.face.shape(0); });
    const double inf = std::numeric_limits<double>::infinity();
    scene.def("trace", &trace, py::arg("origins"), py::arg("directions"),
              py::arg("backend") = "bvh", py::arg("threads") = 0u, py::arg("max_range_m") = inf,
              "Nearest hit of each ray origins[i] + t * directions[i] (normalised), 0 <= t <= "
              "max_range_m; returns Hits.");
    scene.def("occluded", &occluded, py::arg("origins"), py::arg("directions"),
              py::arg("backend") = "bvh", py::arg("threads") = 0u, py::arg("max_range_m") = inf,
              "bool (N,): whether each ray meets anything within [0, max_range_m].");
}

}  // namespace beamtrace::python
