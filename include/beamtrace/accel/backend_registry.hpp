// The table of ray-tracing backends: one line per backend says its name, whether this build has
// it, whether it can run here, how the pipeline should feed it, and how to make it. Every list
// of backends (parse, help texts, the tests' cross-checks, the benchmarks) iterates this table.
//
// Adding a backend (a GPU one, say):
//   1. its traversal in one new file, src/accel/<name>_backend.cpp (a file that needs an external
//      library is compiled only when the library is found, as src/accel/embree_*.cpp is), with
//      a factory for a TriangleMesh and one for a SceneGeometry (detail/ header);
//   2. one value in BackendKind and one line in src/accel/backend_registry.cpp: name, summary,
//      built (a macro from CMake), available (a run-time probe, e.g. "is there a device"),
//      traits (a GPU: large preferred_batch_rays, asynchronous), the two factories (nullptr when
//      not built).
// Nothing else changes: parse_backend_kind, backend_choices, the cross-checks and benchmarks
// pick it up from the table.
#pragma once

#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "beamtrace/accel/backend.hpp"

namespace beamtrace {

struct BackendEntry {
    using MeshFactory = std::unique_ptr<Backend> (*)(const TriangleMesh&, ThreadPool&,
                                                     const BackendConfig&);
    using SceneFactory = std::unique_ptr<Backend> (*)(const SceneGeometry&, ThreadPool&,
                                                      const BackendConfig&);

    BackendKind kind;
    std::string_view name;
    std::string_view summary;
    bool built;  ///< compiled into this build
    /// Whether it can run on this machine now (a built backend may still lack its device).
    bool (*available)();
    BackendTraits traits;
    MeshFactory make_for_mesh;    ///< one mesh; nullptr when not built
    SceneFactory make_for_scene;  ///< instanced meshes and exact spheres; nullptr when not built
    /// What to do to get it when it is not built (for the error message).
    std::string_view how_to_build;

    /// Built and available here.
    [[nodiscard]] bool usable() const { return built && available(); }
};

/// Every backend, in the order of help texts (bvh first: the default without Embree).
[[nodiscard]] std::span<const BackendEntry> backend_registry();
/// The entry of `kind` (every BackendKind has one).
[[nodiscard]] const BackendEntry& backend_entry(BackendKind kind);
/// The entry named `name`, or nullptr.
[[nodiscard]] const BackendEntry* find_backend(std::string_view name);
/// The kinds usable here, in table order.
[[nodiscard]] std::vector<BackendKind> usable_backends();

}  // namespace beamtrace
