// beamtrace.read_las: the points of a LAS or LAZ file as a NumPy structured array, and its header
// as a dict.
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "beamtrace/io/las_reader.hpp"
#include "bindings.hpp"
#include "numpy_arrays.hpp"

namespace beamtrace::python {
namespace {

/// The columns of read_las's array, packed in this order (write_point follows it).
constexpr std::array<Field, 14> kFields{{{"x", "f8"},
                                         {"y", "f8"},
                                         {"z", "f8"},
                                         {"intensity", "u2"},
                                         {"return_number", "u1"},
                                         {"number_of_returns", "u1"},
                                         {"classification", "u1"},
                                         {"gps_time", "f8"},
                                         {"scan_angle", "f4"},
                                         {"point_source_id", "u2"},
                                         {"red", "u2"},
                                         {"green", "u2"},
                                         {"blue", "u2"},
                                         {"user_data", "u1"}}};
constexpr std::size_t kRecordBytes = 3 * 8 + 2 + 3 + 8 + 4 + 2 + 3 * 2 + 1;

py::dtype point_dtype() {
    return structured_dtype(kFields);
}

void write_point(const LasPoint& p, std::uint8_t* record) {
    std::size_t at = 0;
    const auto put = [&](const auto value) { put_field(record, at, value); };
    put(p.x);
    put(p.y);
    put(p.z);
    put(p.intensity);
    put(p.return_number);
    put(p.number_of_returns);
    put(p.classification);
    put(p.gps_time);
    put(p.scan_angle_deg);
    put(p.point_source_id);
    put(p.red);
    put(p.green);
    put(p.blue);
    put(p.user_data);
}

py::tuple vec3_tuple(const Vec3d& v) {
    return py::make_tuple(v.x, v.y, v.z);
}

py::dict header_dict(const LasReader& reader) {
    const LasHeader& h = reader.header();
    py::dict d;
    d["version"] = std::to_string(h.version_major) + "." + std::to_string(h.version_minor);
    d["point_format"] = h.point_format;
    d["point_count"] = h.point_count;
    d["scale"] = vec3_tuple(h.scale);
    d["offset"] = vec3_tuple(h.offset);
    d["min"] = vec3_tuple(h.min);
    d["max"] = vec3_tuple(h.max);
    d["compressed"] = reader.compressed();
    d["system_identifier"] = h.system_identifier;
    d["generating_software"] = h.generating_software;
    return d;
}

// Every point of `reader` into `out` (point_count records of kRecordBytes).
void read_points(LasReader& reader, std::uint8_t* out) {
    const std::uint64_t count = reader.header().point_count;
    std::vector<LasPoint> chunk(
        static_cast<std::size_t>(std::min<std::uint64_t>(LasReader::kChunkPoints, count)));
    std::uint64_t done = 0;
    while (const std::size_t n = reader.read(chunk)) {
        for (std::size_t i = 0; i < n; ++i) {
            write_point(chunk[i], out + (done + i) * kRecordBytes);
        }
        done += n;
    }
}

py::tuple read_las(const std::filesystem::path& path, unsigned threads) {
    std::unique_ptr<LasReader> reader;
    {
        py::gil_scoped_release release;
        reader = std::make_unique<LasReader>(path, threads);
    }
    const py::dtype dtype = point_dtype();
    if (static_cast<std::size_t>(dtype.itemsize()) != kRecordBytes) {
        throw std::logic_error("read_las: point dtype is not packed");
    }
    const std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(reader->header().point_count)};
    py::array points(dtype, shape);
    auto* out = static_cast<std::uint8_t*>(points.mutable_data());
    {
        py::gil_scoped_release release;
        read_points(*reader, out);
    }
    return py::make_tuple(points, header_dict(*reader));
}

}  // namespace

void bind_las(py::module_& m) {
    m.def("read_las", &read_las, py::arg("path"), py::arg("threads") = 0u,
          "(points, header) of a LAS or LAZ file: points a structured array (x, y, z, intensity, "
          "return_number, number_of_returns, classification, gps_time, scan_angle, "
          "point_source_id, red, green, blue), header a dict. threads: LAZ chunks decoded in "
          "parallel (0: every hardware thread).");
}

}  // namespace beamtrace::python
