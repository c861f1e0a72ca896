// Axis-aligned bounding box.
#pragma once

#include <limits>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct Aabb {
    Vec3f lo{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
             std::numeric_limits<float>::infinity()};
    Vec3f hi{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
             -std::numeric_limits<float>::infinity()};

    void extend(const Vec3f& p) {
        lo = min(lo, p);
        hi = max(hi, p);
    }
    void extend(const Aabb& b) {
        lo = min(lo, b.lo);
        hi = max(hi, b.hi);
    }
    [[nodiscard]] bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    [[nodiscard]] Vec3f extent() const { return hi - lo; }
    [[nodiscard]] Vec3f center() const { return (lo + hi) * 0.5f; }
    /// Half the surface area (what SAH costs compare); 0 for an empty box.
    [[nodiscard]] float half_area() const {
        if (empty()) {
            return 0.0f;
        }
        const Vec3f e = extent();
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
};

}  // namespace beamtrace
