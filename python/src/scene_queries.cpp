// Scene.trace (nearest hits as NumPy arrays) and Scene.occluded, the GIL released while tracing.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "beamtrace/core/hit_batch.hpp"
#include "beamtrace/core/ray_batch.hpp"
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

/// Where trace writes its results: the data of the NumPy arrays it returns (freshly allocated,
/// not initialised: every element is written once, by the thread that traces its ray).
struct HitPointers {
    float *t, *u, *v;
    std::int64_t *face, *part, *label;
    double* normal;  ///< 3 per ray
};

/// The buffers of one step of rays (rays_per_step): converted rays and their nearest hits, small
/// enough to stay in the cache between tracing them and writing them out.
struct BlockScratch {
    RayBatch rays;
    HitBatch hits;
};

// Writes the hits of `s` (rays first.. of the call) where `out` says: range, barycentrics, face,
// part, label and normal (a miss: -1, normal 0).
void describe_hits(const Scene& scene, const BlockScratch& s, std::size_t first,
                   const HitPointers& out) {
    for (std::size_t j = 0; j < s.rays.size(); ++j) {
        const std::size_t i = first + j;
        out.t[i] = s.hits.t[j];
        out.u[i] = s.hits.u[j];
        out.v[i] = s.hits.v[j];
        double* nrm = out.normal + 3 * i;
        if (!s.hits.hit(j)) {
            out.face[i] = out.part[i] = out.label[i] = -1;
            nrm[0] = nrm[1] = nrm[2] = 0.0;
            continue;
        }
        const std::uint32_t f = s.hits.face[j];
        const std::size_t p = scene.part_of_face(f);
        const Vec3d at = s.rays.origin(j) + s.rays.direction(j) * static_cast<double>(s.hits.t[j]);
        const Vec3d n = scene.geometry.normal_at(f, at);
        out.face[i] = f;
        out.part[i] = static_cast<std::int64_t>(p);
        out.label[i] = scene.parts[p].label;
        nrm[0] = n.x;
        nrm[1] = n.y;
        nrm[2] = n.z;
    }
}

// Rays traced and then described in one step on a CPU backend: few enough that the faces and
// vertices their traversals ended on are still in the L1/L2 cache when their normals are looked
// up. With 4096 (the backends' preferred batch) the normal lookup read them from memory again and
// trace lost about 5 % of the C++ rate over the 1.48 M-triangle DEM (CPU time,
// bench/python/trace_rate.py); 256 and 64 did equally well.
constexpr std::size_t kRaysPerStep = 256;

// An asynchronous backend (a GPU) is fed the batches it asks for.
std::size_t rays_per_step(const BackendTraits& t) {
    const std::size_t preferred = std::max<std::size_t>(1, t.preferred_batch_rays);
    return t.asynchronous ? preferred : std::min(preferred, kRaysPerStep);
}

// Converts, traces and describes rays [begin, end) step by step, each step's rays while they
// are in the cache: the rays go from the caller's arrays to the results in the returned arrays
// without a batch of all rays in between (which cost a serial zero fill, 64 bytes a ray written and
// read back, and a describe pass that read the faces from memory again). Returns the first bad row,
// or rows.size().
std::size_t trace_rows(const Scene& scene, const Backend& b, const RayRows& rows, std::size_t begin,
                       std::size_t end, const HitPointers& out) {
    BlockScratch s;        // a few KB, reused by the steps
    ThreadPool serial(1);  // no workers: this thread traces the steps
    const std::size_t step = rays_per_step(b.traits());
    for (std::size_t first = begin; first < end; first += step) {
        const std::size_t last = std::min(end, first + step);
        s.rays.resize(last - first);
        if (const std::size_t bad = rows.convert(first, last, s.rays, 0); bad < rows.size()) {
            return bad;  // the rest of this range cannot hold a lower bad row
        }
        s.hits.resize(last - first);
        b.intersect(s.rays, 0, last - first, s.hits, serial);
        describe_hits(scene, s, first, out);
    }
    return rows.size();
}

template <typename T>
T* data_of(py::array& a) {
    return static_cast<T*>(a.mutable_data());
}

Hits trace(PyScene& self, const py::handle& origins, const py::handle& directions,
           const std::string& backend, unsigned threads, double max_range_m) {
    const BackendKind kind = parse_backend_kind(backend);
    const RayRows rows(origins, directions, max_range_m);
    const auto n = static_cast<py::ssize_t>(rows.size());
    // NumPy allocates them, uninitialised (np.empty): their pages are first touched by the
    // threads that write them, inside the parallel loop.
    Hits h{py::array_t<float>(n),
           py::array_t<std::int64_t>(n),
           py::array_t<std::int64_t>(n),
           py::array_t<std::int64_t>(n),
           py::array_t<float>(n),
           py::array_t<float>(n),
           py::array_t<double>({n, py::ssize_t{3}})};
    const HitPointers out{data_of<float>(h.range_m),     data_of<float>(h.u),
                          data_of<float>(h.v),           data_of<std::int64_t>(h.face),
                          data_of<std::int64_t>(h.part), data_of<std::int64_t>(h.label),
                          data_of<double>(h.normal)};
    std::atomic<std::size_t> first_bad{rows.size()};
    {
        py::gil_scoped_release release;
        ThreadPool pool(threads);
        const Backend& b = self.backend(kind, pool);
        pool.parallel_for(
            rows.size(), b.traits().preferred_batch_rays, [&](std::size_t begin, std::size_t end) {
                const std::size_t bad = trace_rows(self.scene(), b, rows, begin, end, out);
                std::size_t seen = first_bad.load();
                while (bad < seen && !first_bad.compare_exchange_weak(seen, bad)) {
                }
            });
    }
    if (first_bad.load() < rows.size()) {
        rows.raise_bad_row(first_bad.load());
    }
    return h;
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
