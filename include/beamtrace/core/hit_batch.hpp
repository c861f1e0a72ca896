// Structure-of-arrays results of ray queries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace beamtrace {

/// Face ID of a miss (written as -1 in CSV files).
inline constexpr std::uint32_t kNoFace = std::numeric_limits<std::uint32_t>::max();

/// Nearest hits, one slot per ray. A miss has t = +inf and face = kNoFace.
struct HitBatch {
    std::vector<float> t;             ///< range along the ray, metres for unit directions
    std::vector<std::uint32_t> face;  ///< face ID in the scene's triangle set
    std::vector<float> u, v;          ///< barycentrics of V1 and V2

    [[nodiscard]] std::size_t size() const { return t.size(); }
    [[nodiscard]] bool hit(std::size_t i) const { return face[i] != kNoFace; }
    void resize(std::size_t n) {
        t.assign(n, std::numeric_limits<float>::infinity());
        face.assign(n, kNoFace);
        u.assign(n, 0.0f);
        v.assign(n, 0.0f);
    }
};

/// Every hit of every ray, sorted by (t, face) per ray. Hits of ray i are the entries
/// [offsets[i], offsets[i+1]).
struct AllHits {
    std::vector<std::size_t> offsets{0};
    std::vector<float> t;
    std::vector<std::uint32_t> face;
    std::vector<std::uint8_t> front;  ///< 1 when the ray met the front side

    [[nodiscard]] std::size_t ray_count() const { return offsets.size() - 1; }
    [[nodiscard]] std::size_t count(std::size_t ray) const {
        return offsets[ray + 1] - offsets[ray];
    }
};

}  // namespace beamtrace
