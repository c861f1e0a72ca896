// Factories of the own backends (backends.cpp) for the registry (backend_registry.cpp).
#pragma once

#include <memory>

#include "beamtrace/accel/backend.hpp"

namespace beamtrace::detail {

[[nodiscard]] std::unique_ptr<Backend> make_brute_backend(const TriangleMesh& mesh,
                                                          ThreadPool& pool,
                                                          const BackendConfig& config);
[[nodiscard]] std::unique_ptr<Backend> make_brute_backend(const SceneGeometry& geometry,
                                                          ThreadPool& pool,
                                                          const BackendConfig& config);
[[nodiscard]] std::unique_ptr<Backend> make_kdtree_backend(const TriangleMesh& mesh,
                                                           ThreadPool& pool,
                                                           const BackendConfig& config);
[[nodiscard]] std::unique_ptr<Backend> make_kdtree_backend(const SceneGeometry& geometry,
                                                           ThreadPool& pool,
                                                           const BackendConfig& config);
[[nodiscard]] std::unique_ptr<Backend> make_bvh_backend(const TriangleMesh& mesh, ThreadPool& pool,
                                                        const BackendConfig& config);
[[nodiscard]] std::unique_ptr<Backend> make_bvh_backend(const SceneGeometry& geometry,
                                                        ThreadPool& pool,
                                                        const BackendConfig& config);

}  // namespace beamtrace::detail
