#include "rays.hpp"

#include <cmath>
#include <string>

#include "numpy_arrays.hpp"

namespace beamtrace::python {
namespace {

[[noreturn]] void bad_row(const char* name, py::ssize_t row, const char* problem) {
    throw py::value_error(std::string(name) + ": row " + std::to_string(row) + " " + problem);
}

bool finite(const Vec3d& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

RayBatch make_rays(const py::handle& origins, const py::handle& directions, double max_range_m) {
    const CArray<double> o = vec3_array(origins, "origins");
    const CArray<double> d = vec3_array(directions, "directions");
    if (o.shape(0) != d.shape(0)) {
        throw py::value_error("directions: " + std::to_string(d.shape(0)) +
                              " rows, but origins has " + std::to_string(o.shape(0)));
    }
    if (!(max_range_m > 0.0)) {
        throw py::value_error("max_range_m: " + std::to_string(max_range_m) +
                              ", expected a positive range (inf: no limit)");
    }
    const auto ov = o.unchecked<2>();
    const auto dv = d.unchecked<2>();
    RayBatch rays;
    rays.resize(static_cast<std::size_t>(o.shape(0)));
    for (py::ssize_t i = 0; i < o.shape(0); ++i) {
        const Vec3d org{ov(i, 0), ov(i, 1), ov(i, 2)};
        const Vec3d dir{dv(i, 0), dv(i, 1), dv(i, 2)};
        if (!finite(org)) {
            bad_row("origins", i, "is not finite");
        }
        if (!finite(dir)) {
            bad_row("directions", i, "is not finite");
        }
        const double len = length(dir);
        if (!(len > 0.0)) {
            bad_row("directions", i, "has zero length");
        }
        if (!std::isfinite(len)) {
            bad_row("directions", i, "is too long to normalise");
        }
        rays.set(static_cast<std::size_t>(i), org, dir * (1.0 / len), 0.0, max_range_m);
    }
    return rays;
}

}  // namespace beamtrace::python
