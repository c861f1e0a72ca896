// Scene.all_hits: every hit of every ray (Backend::intersect_all) as ragged NumPy arrays, the
// GIL released while tracing.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "numpy_arrays.hpp"
#include "py_scene.hpp"
#include "rays.hpp"

namespace beamtrace::python {
namespace {

/// Every hit of N rays, M hits in all, ray by ray, each ray's hits by increasing range (then
/// face). offsets (N + 1,): the hits of ray i are rows offsets[i] to offsets[i + 1].
struct AllHitsArrays {
    py::array offsets, ray, range_m, face, part, label, front;
};

Facing parse_facing(const std::string& name) {
    if (name == "both") {
        return Facing::both;
    }
    if (name == "front") {
        return Facing::front;
    }
    if (name == "back") {
        return Facing::back;
    }
    throw ConfigError("facing: '" + name + "', expected both, front or back");
}

// The per-hit columns before they become arrays (filled with the GIL released).
struct AllHitsOutput {
    AllHits hits;
    std::vector<std::int64_t> offsets, ray, face, part, label;
};

void describe(const Scene& scene, AllHitsOutput& out) {
    const std::size_t n = out.hits.ray_count(), m = out.hits.t.size();
    out.offsets.assign(out.hits.offsets.begin(), out.hits.offsets.end());
    out.ray.resize(m);
    out.face.resize(m);
    out.part.resize(m);
    out.label.resize(m);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = out.hits.offsets[i]; k < out.hits.offsets[i + 1]; ++k) {
            const std::uint32_t f = out.hits.face[k];
            const std::size_t p = scene.part_of_face(f);
            out.ray[k] = static_cast<std::int64_t>(i);
            out.face[k] = f;
            out.part[k] = static_cast<std::int64_t>(p);
            out.label[k] = scene.parts[p].label;
        }
    }
}

AllHitsArrays all_hits(PyScene& self, const py::handle& origins, const py::handle& directions,
                       const std::string& backend, unsigned threads, double max_range_m,
                       const std::string& facing) {
    const BackendKind kind = parse_backend_kind(backend);
    const Facing sides = parse_facing(facing);
    ThreadPool pool(threads);
    const RayBatch rays = make_rays(origins, directions, max_range_m, pool);
    AllHitsOutput out;
    {
        py::gil_scoped_release release;
        self.backend(kind, pool).intersect_all(rays, sides, out.hits, pool);
        describe(self.scene(), out);
    }
    const auto n = static_cast<py::ssize_t>(rays.size());
    const auto m = static_cast<py::ssize_t>(out.hits.t.size());
    AllHitsArrays a;
    a.offsets = to_numpy(std::move(out.offsets), {n + 1});
    a.ray = to_numpy(std::move(out.ray), {m});
    a.range_m = to_numpy(std::move(out.hits.t), {m});
    a.face = to_numpy(std::move(out.face), {m});
    a.part = to_numpy(std::move(out.part), {m});
    a.label = to_numpy(std::move(out.label), {m});
    // One byte per hit, 0 or 1: NumPy's bool layout.
    a.front = to_numpy(std::move(out.hits.front), {m}).attr("view")(py::dtype::of<bool>());
    return a;
}

}  // namespace

void bind_scene_all_hits(py::module_& m, py::class_<PyScene>& scene) {
    py::class_<AllHitsArrays>(m, "AllHits",
                              "Every hit of Scene.all_hits, one row per hit, ray by ray, each "
                              "ray's hits by increasing range")
        .def_readonly("offsets", &AllHitsArrays::offsets,
                      "int64 (N + 1,): the hits of ray i are rows offsets[i]:offsets[i + 1]")
        .def_readonly("ray", &AllHitsArrays::ray, "int64 (M,): the ray of each hit")
        .def_readonly("range_m", &AllHitsArrays::range_m, "float32 (M,): metres")
        .def_readonly("face", &AllHitsArrays::face, "int64 (M,): face ID")
        .def_readonly("part", &AllHitsArrays::part, "int64 (M,): index into Scene.parts")
        .def_readonly("label", &AllHitsArrays::label, "int64 (M,): the part's class")
        .def_readonly("front", &AllHitsArrays::front,
                      "bool (M,): the ray met the face's front side")
        .def("__len__", [](const AllHitsArrays& a) { return a.ray.shape(0); });
    const double inf = std::numeric_limits<double>::infinity();
    scene.def("all_hits", &all_hits, py::arg("origins"), py::arg("directions"),
              py::arg("backend") = "bvh", py::arg("threads") = 0u, py::arg("max_range_m") = inf,
              py::arg("facing") = "both",
              "Every hit of each ray origins[i] + t * directions[i] (normalised), 0 <= t <= "
              "max_range_m, on the sides `facing` (both, front or back); returns AllHits.");
}

}  // namespace beamtrace::python
