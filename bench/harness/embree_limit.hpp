// The practical limit of CPU ray tracing, for benchmarks: Intel Embree called directly on a
// batch of rays, with nothing else in the loop (no face-ID mapping, no tie rules). Exists only in
// builds with Embree (BEAMTRACE_HAVE_EMBREE).
#pragma once

#ifdef BEAMTRACE_HAVE_EMBREE

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/geometry/triangle_mesh.hpp"

namespace beamtrace {

enum class EmbreeCall : std::uint8_t {
    single,    ///< one rtcIntersect1 per ray
    packet16,  ///< rtcIntersect16 on 16 consecutive rays, incoherent (what our backend does)
    packet16_coherent  ///< rtcIntersect16 with the coherent flag (fastest on coherent rays, but
                       ///< not watertight in Embree 3.13: rays through shared edges can slip)
};
[[nodiscard]] std::string_view to_string(EmbreeCall call);

class EmbreeLimit {
  public:
    /// One Embree scene over `mesh` (vertices copied once into an Embree buffer, indices
    /// shared: `mesh` must outlive this), built with `threads` Embree threads.
    EmbreeLimit(const TriangleMesh& mesh, unsigned threads);
    ~EmbreeLimit();
    EmbreeLimit(const EmbreeLimit&) = delete;
    EmbreeLimit& operator=(const EmbreeLimit&) = delete;

    /// Nearest hit of every ray: face[i] is the primitive ID or kNoFace. The rays are cut into
    /// chunks of 1024 for the pool.
    void trace(const RayBatch& rays, EmbreeCall call, std::vector<std::uint32_t>& face,
               ThreadPool& pool) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace beamtrace

#endif  // BEAMTRACE_HAVE_EMBREE
