// Factory of the Embree backend (embree_backend.cpp, compiled only with BEAMTRACE_HAVE_EMBREE).
#pragma once

#include <memory>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/error.hpp"

namespace beamtrace::detail {

#ifdef BEAMTRACE_HAVE_EMBREE
[[nodiscard]] std::unique_ptr<Backend> make_embree_backend(const TriangleMesh& mesh,
                                                           ThreadPool& pool);
[[nodiscard]] std::unique_ptr<Backend> make_embree_backend(const SceneGeometry& geometry,
                                                           ThreadPool& pool);
#else
template <class Geometry>
[[nodiscard]] std::unique_ptr<Backend> make_embree_backend(const Geometry& /*geometry*/,
                                                           ThreadPool& /*pool*/) {
    throw ConfigError("backend 'embree': beamtrace was built without Embree");
}
#endif

}  // namespace beamtrace::detail
