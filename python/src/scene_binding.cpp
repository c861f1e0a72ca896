// beamtrace.Scene: its constructors (load, from_arrays) and what it holds (parts, counts, origin).
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "py_scene.hpp"

namespace beamtrace::python {
namespace {

py::tuple vec3_tuple(const Vec3d& v) {
    return py::make_tuple(v.x, v.y, v.z);
}

py::list parts_list(const PyScene& self) {
    py::list out;
    for (const ScenePart& p : self.scene().parts) {
        py::dict d;
        d["name"] = p.name;
        d["first_face"] = p.first_face;
        d["face_count"] = p.face_count;
        d["label"] = p.label;
        d["part_id"] = p.part_id;
        d["material"] = p.material;
        out.append(d);
    }
    return out;
}

py::tuple bounds_tuple(const PyScene& self) {
    const Aabb b = self.scene().geometry.bounds();
    return py::make_tuple(vec3_tuple(Vec3d(b.lo)), vec3_tuple(Vec3d(b.hi)));
}

}  // namespace

void bind_scene(py::module_& m) {
    py::class_<PyScene> scene(m, "Scene", "Triangles (and exact spheres) to trace rays against");
    scene.def_static("load", &load_scene, py::arg("path"),
                     "A scene file (.yaml/.yml) or a mesh file (OBJ, PLY, STL, glTF/GLB).");
    scene.def_static("from_arrays", &scene_from_arrays, py::arg("vertices"), py::arg("faces"),
                     py::arg("labels") = py::none(),
                     "One mesh: vertices (n, 3) metres, faces (m, 3) vertex indices, labels "
                     "(m,) classes 0-255 or None (1). Consecutive faces of one label: one part.");
    scene.def_property_readonly("face_count",
                                [](const PyScene& s) { return s.scene().geometry.face_count(); });
    scene.def_property_readonly("triangle_count",
                                [](const PyScene& s) { return s.scene().triangle_count(); });
    scene.def_property_readonly(
        "origin_m", [](const PyScene& s) { return vec3_tuple(s.scene().origin_m); },
        "World position of the scene's local origin (rays and hits are in scene coordinates)");
    scene.def_property_readonly("bounds", &bounds_tuple,
                                "((xmin, ymin, zmin), (xmax, ymax, zmax)), scene coordinates");
    scene.def_property_readonly("parts", &parts_list,
                                "list of dicts: name, first_face, face_count, label, part_id, "
                                "material");
    bind_scene_queries(m, scene);
    bind_scene_all_hits(m, scene);
    bind_scene_bench(scene);
}

}  // namespace beamtrace::python
