// Structure-of-arrays batch of rays in double precision (what sensors produce).
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

struct RayBatch {
    std::vector<double> ox, oy, oz;  ///< origins, metres
    std::vector<double> dx, dy, dz;  ///< directions (unit length for sensor rays)
    std::vector<double> tmin, tmax;  ///< valid range interval along the ray, metres

    [[nodiscard]] std::size_t size() const { return ox.size(); }
    [[nodiscard]] bool empty() const { return ox.empty(); }

    void resize(std::size_t n) {
        ox.resize(n);
        oy.resize(n);
        oz.resize(n);
        dx.resize(n);
        dy.resize(n);
        dz.resize(n);
        tmin.resize(n, 0.0);
        tmax.resize(n, std::numeric_limits<double>::infinity());
    }
    void reserve(std::size_t n) {
        for (auto* v : {&ox, &oy, &oz, &dx, &dy, &dz, &tmin, &tmax}) {
            v->reserve(n);
        }
    }
    void set(std::size_t i, const Vec3d& o, const Vec3d& d, double t0 = 0.0,
             double t1 = std::numeric_limits<double>::infinity()) {
        ox[i] = o.x;
        oy[i] = o.y;
        oz[i] = o.z;
        dx[i] = d.x;
        dy[i] = d.y;
        dz[i] = d.z;
        tmin[i] = t0;
        tmax[i] = t1;
    }
    void push_back(const Vec3d& o, const Vec3d& d, double t0 = 0.0,
                   double t1 = std::numeric_limits<double>::infinity()) {
        ox.push_back(o.x);
        oy.push_back(o.y);
        oz.push_back(o.z);
        dx.push_back(d.x);
        dy.push_back(d.y);
        dz.push_back(d.z);
        tmin.push_back(t0);
        tmax.push_back(t1);
    }
    [[nodiscard]] Vec3d origin(std::size_t i) const { return {ox[i], oy[i], oz[i]}; }
    [[nodiscard]] Vec3d direction(std::size_t i) const { return {dx[i], dy[i], dz[i]}; }
};

}  // namespace beamtrace
