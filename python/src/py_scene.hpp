// beamtrace.Scene: a Scene and the backends built over it (each kind once, at first use).
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/scene/scene.hpp"
#include "bindings.hpp"

namespace beamtrace::python {

class PyScene {
  public:
    explicit PyScene(Scene scene) : scene_(std::move(scene)) {}
    PyScene(const PyScene&) = delete;
    PyScene& operator=(const PyScene&) = delete;

    [[nodiscard]] const Scene& scene() const { return scene_; }
    /// The backend of `kind` over this scene, built with `pool` at its first use. Safe to call
    /// from several threads (the GIL is released while tracing).
    [[nodiscard]] const Backend& backend(BackendKind kind, ThreadPool& pool);

  private:
    Scene scene_;  ///< never moves: the backends point into its geometry
    std::mutex mutex_;
    std::map<BackendKind, std::unique_ptr<Backend>> backends_;
};

/// A scene file (.yaml/.yml, as `survey` and `render` load `scene:`) or one mesh file (OBJ, PLY,
/// STL, glTF). Library errors propagate (InputError names the file).
[[nodiscard]] std::unique_ptr<PyScene> load_scene(const std::filesystem::path& path);

/// A scene of one mesh from NumPy arrays: vertices (n, 3) metres, faces (m, 3) vertex indices,
/// labels (m,) per-face classes 0-255 or None (all 1). Each run of consecutive faces with the
/// same label is one part. Raises ValueError naming the argument for bad arrays.
[[nodiscard]] std::unique_ptr<PyScene> scene_from_arrays(const py::handle& vertices,
                                                         const py::handle& faces,
                                                         const py::handle& labels);

/// Registers Scene.trace, Scene.occluded and the Hits class on `scene`.
void bind_scene_queries(py::module_& m, py::class_<PyScene>& scene);
/// Registers Scene.all_hits and the AllHits class on `scene`.
void bind_scene_all_hits(py::module_& m, py::class_<PyScene>& scene);
/// Registers Scene._intersect_seconds (the C++ rate for bench/python/trace_rate.py) on `scene`.
void bind_scene_bench(py::class_<PyScene>& scene);

}  // namespace beamtrace::python
