// Scene.load and Scene.from_arrays.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "beamtrace/scene/scene_builder.hpp"
#include "numpy_arrays.hpp"
#include "py_scene.hpp"

namespace beamtrace::python {
namespace {

std::string lower_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

TriangleMesh mesh_from_arrays(const py::handle& vertices, const py::handle& faces) {
    const CArray<double> v = vec3_array(vertices, "vertices");
    const CArray<std::int64_t> f = index_array(faces, "faces", 2);
    if (f.shape(0) == 0) {
        throw py::value_error("faces: shape (0, 3), expected at least one face");
    }
    const auto vv = v.unchecked<2>();
    const auto fv = f.unchecked<2>();
    TriangleMesh mesh;
    mesh.vertices.reserve(static_cast<std::size_t>(v.shape(0)));
    for (py::ssize_t i = 0; i < v.shape(0); ++i) {
        // Stored as float, as the mesh loaders store them: a double beyond float is refused too.
        const Vec3f p(Vec3d{vv(i, 0), vv(i, 1), vv(i, 2)});
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw py::value_error("vertices: row " + std::to_string(i) + " is not finite");
        }
        mesh.vertices.push_back(p);
    }
    mesh.faces.resize(static_cast<std::size_t>(f.shape(0)));
    for (py::ssize_t i = 0; i < f.shape(0); ++i) {
        for (py::ssize_t k = 0; k < 3; ++k) {
            const std::int64_t index = fv(i, k);
            if (index < 0 || index >= v.shape(0)) {
                throw py::value_error("faces: row " + std::to_string(i) + " has vertex index " +
                                      std::to_string(index) + ", expected 0 to " +
                                      std::to_string(v.shape(0) - 1));
            }
            mesh.faces[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] =
                static_cast<std::uint32_t>(index);
        }
    }
    return mesh;
}

// Per-face labels (m,) as classes 0-255; all 1 (unclassified) for None.
std::vector<std::uint8_t> face_labels(const py::handle& labels, std::size_t faces) {
    if (labels.is_none()) {
        return std::vector<std::uint8_t>(faces, 1);
    }
    const CArray<std::int64_t> l = index_array(labels, "labels", 1);
    if (static_cast<std::size_t>(l.shape(0)) != faces) {
        throw py::value_error("labels: shape " + shape_text(l) + ", expected (" +
                              std::to_string(faces) + ",), one per face");
    }
    std::vector<std::uint8_t> out(faces);
    const auto lv = l.unchecked<1>();
    for (std::size_t i = 0; i < faces; ++i) {
        const std::int64_t c = lv(static_cast<py::ssize_t>(i));
        if (c < 0 || c > 255) {
            throw py::value_error("labels: row " + std::to_string(i) + " is " + std::to_string(c) +
                                  ", expected a class 0-255");
        }
        out[i] = static_cast<std::uint8_t>(c);
    }
    return out;
}

}  // namespace

std::unique_ptr<PyScene> load_scene(const std::filesystem::path& path) {
    const std::string ext = lower_extension(path);
    Scene scene;
    {
        py::gil_scoped_release release;
        scene = ext == ".yaml" || ext == ".yml" ? load_scene_file(path) : load_scene_meshes({path});
    }
    return std::make_unique<PyScene>(std::move(scene));
}

std::unique_ptr<PyScene> scene_from_arrays(const py::handle& vertices, const py::handle& faces,
                                           const py::handle& labels) {
    const TriangleMesh mesh = mesh_from_arrays(vertices, faces);
    const std::vector<std::uint8_t> classes = face_labels(labels, mesh.faces.size());
    Scene scene;
    scene.geometry.append_flat(mesh);
    for (std::size_t first = 0; first < classes.size();) {
        std::size_t end = first + 1;
        while (end < classes.size() && classes[end] == classes[first]) {
            ++end;
        }
        ScenePart part;
        part.name = "arrays";
        part.first_face = static_cast<std::uint32_t>(first);
        part.face_count = static_cast<std::uint32_t>(end - first);
        part.label = classes[first];
        part.part_id =
            static_cast<std::uint16_t>(std::min<std::size_t>(scene.parts.size() + 1, 65535));
        part.instance_count = 1;
        scene.parts.push_back(std::move(part));
        first = end;
    }
    return std::make_unique<PyScene>(std::move(scene));
}

const Backend& PyScene::backend(BackendKind kind, ThreadPool& pool) {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto& slot = backends_[kind];
    if (!slot) {
        slot = make_backend(kind, scene_.geometry, pool);
    }
    return *slot;
}

}  // namespace beamtrace::python
