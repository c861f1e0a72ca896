// The backend table (see backend_registry.hpp for how to add one) and the public functions of
// backend.hpp as thin wrappers over it.
#include "beamtrace/accel/backend_registry.hpp"

#include <array>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/name_table.hpp"
#include "detail/embree.hpp"
#include "detail/own_backends.hpp"

namespace beamtrace {
namespace {

bool always() {
    return true;
}

/// CPU backends traverse ray by ray in the pipeline's blocks of 1024 pulses; the oracles trace a
/// flattened copy of an instanced scene.
constexpr BackendTraits kCpuRays{1024, false, false, false};
/// The BVH traces neighbouring coherent rays of one mesh in packets (BvhTraceConfig).
constexpr BackendTraits kBvh{1024, true, false, true};

#ifdef BEAMTRACE_HAVE_EMBREE
constexpr BackendEntry::MeshFactory kEmbreeMesh = [](const TriangleMesh& m, ThreadPool& pool,
                                                     const BackendConfig&) {
    return detail::make_embree_backend(m, pool);
};
constexpr BackendEntry::SceneFactory kEmbreeScene = [](const SceneGeometry& g, ThreadPool& pool,
                                                       const BackendConfig&) {
    return detail::make_embree_backend(g, pool);
};
#else
constexpr BackendEntry::MeshFactory kEmbreeMesh = nullptr;
constexpr BackendEntry::SceneFactory kEmbreeScene = nullptr;
#endif

using detail::make_brute_backend;
using detail::make_bvh_backend;
using detail::make_kdtree_backend;

// clang-format off
constexpr std::array kBackends{
    BackendEntry{BackendKind::bvh, "bvh", "binned-SAH BVH (two-level over instances)", true,
                 always, kBvh, make_bvh_backend, make_bvh_backend, ""},
    BackendEntry{BackendKind::kdtree, "kdtree", "SAH k-d tree (or the ladar report's rules)", true,
                 always, kCpuRays, make_kdtree_backend, make_kdtree_backend, ""},
    BackendEntry{BackendKind::brute, "brute", "every ray against every triangle (the oracle)", true,
                 always, kCpuRays, make_brute_backend, make_brute_backend, ""},
    // Packets of 16 neighbouring rays (rtcIntersect16).
    BackendEntry{BackendKind::embree, "embree", "Embree 3", embree_available(), always,
                 BackendTraits{1024, true, false, true}, kEmbreeMesh, kEmbreeScene,
                 "install libembree-dev and reconfigure with -DBEAMTRACE_WITH_EMBREE=ON"},
};
// clang-format on

std::vector<std::string_view> built_names() {
    std::vector<std::string_view> names;
    for (const auto& e : kBackends) {
        if (e.built) {
            names.push_back(e.name);
        }
    }
    return names;
}

}  // namespace

std::span<const BackendEntry> backend_registry() {
    return kBackends;
}

const BackendEntry& backend_entry(BackendKind kind) {
    for (const auto& e : kBackends) {
        if (e.kind == kind) {
            return e;
        }
    }
    throw ConfigError("backend kind " + std::to_string(static_cast<int>(kind)) +
                      " is not in the backend registry");
}

const BackendEntry* find_backend(std::string_view name) {
    for (const auto& e : kBackends) {
        if (e.name == name) {
            return &e;
        }
    }
    return nullptr;
}

std::vector<BackendKind> usable_backends() {
    std::vector<BackendKind> kinds;
    for (const auto& e : kBackends) {
        if (e.usable()) {
            kinds.push_back(e.kind);
        }
    }
    return kinds;
}

std::string backend_choices() {
    std::string out;
    for (const auto name : built_names()) {
        out += (out.empty() ? "" : " | ") + std::string(name);
    }
    return out;
}

BackendKind parse_backend_kind(std::string_view name) {
    const BackendEntry* e = find_backend(name);
    if (e == nullptr) {
        throw ConfigError("unknown backend '" + std::string(name) + "' (expected " +
                          backend_choices() + ")");
    }
    if (!e->built) {
        throw ConfigError("backend '" + std::string(name) + "': beamtrace was built without " +
                          std::string(e->summary) + " (" + std::string(e->how_to_build) + ")");
    }
    if (!e->available()) {
        throw ConfigError("backend '" + std::string(name) + "' is not available on this machine");
    }
    return e->kind;
}

std::string_view to_string(BackendKind kind) {
    for (const auto& e : kBackends) {
        if (e.kind == kind) {
            return e.name;
        }
    }
    return "?";
}

const BackendTraits& Backend::traits() const {
    return backend_entry(kind()).traits;
}

namespace {

const BackendEntry& usable_entry(BackendKind kind) {
    const BackendEntry& e = backend_entry(kind);
    if (!e.built || e.make_for_mesh == nullptr || e.make_for_scene == nullptr) {
        throw ConfigError("backend '" + std::string(e.name) + "': beamtrace was built without " +
                          std::string(e.summary));
    }
    return e;
}

}  // namespace

std::unique_ptr<Backend> make_backend(BackendKind kind, const TriangleMesh& mesh, ThreadPool& pool,
                                      const BackendConfig& config) {
    return usable_entry(kind).make_for_mesh(mesh, pool, config);
}

std::unique_ptr<Backend> make_backend(BackendKind kind, const SceneGeometry& geometry,
                                      ThreadPool& pool, const BackendConfig& config) {
    const BackendEntry& e = usable_entry(kind);
    if (geometry.is_single_mesh()) {
        return e.make_for_mesh(geometry.meshes[geometry.instances[0].mesh], pool, config);
    }
    return e.make_for_scene(geometry, pool, config);
}

}  // namespace beamtrace
