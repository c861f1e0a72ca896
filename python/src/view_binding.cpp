// beamtrace.view: `beamtrace view FILES --camera ... --output v.png` as one call (ViewJobConfig,
// the CLI's settings and defaults), the image returned as an (h, w, 3) uint8 array instead of a
// PNG; the GIL released while the sections load and the image renders.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/heightfield/data_framing.hpp"
#include "beamtrace/heightfield/view_job.hpp"
#include "bindings.hpp"
#include "camera_text.hpp"
#include "numpy_arrays.hpp"

namespace beamtrace::python {
namespace {

/// What view() was given, besides the files.
struct ViewArgs {
    py::object camera;
    std::pair<int, int> size;
    double fov_deg, cell_size;
    int levels, section_cells, sections;
    py::object memory_budget;
    std::string color;
    int height_stacks;
    double stack_gap;
    int fill_gaps;
    double eye_dome, fog;
    bool shading;
    unsigned threads;
};

ViewJobConfig view_job(std::vector<std::filesystem::path> files, const ViewArgs& a) {
    ViewJobConfig job;
    job.inputs = std::move(files);
    if (!a.camera.is_none()) {
        job.pose = parse_camera_pose(position_text(a.camera), "--camera").pose;
    }
    job.camera.width = a.size.first;
    job.camera.height = a.size.second;
    job.camera.hfov_deg = a.fov_deg;
    HeightFieldConfig& f = job.session.field;
    f.cell_size = a.cell_size;
    f.levels = a.levels;
    f.section_cells = a.section_cells;
    f.sections = a.sections;
    f.memory_budget_bytes = py::isinstance<py::str>(a.memory_budget)
                                ? parse_byte_size(a.memory_budget.cast<std::string>())
                                : a.memory_budget.cast<std::uint64_t>();
    f.color = parse_color_mode(a.color);
    f.height_stacks = a.height_stacks;
    f.stack_gap = a.stack_gap;
    f.gap_fill_cells = a.fill_gaps;
    job.session.threads = a.threads;
    job.render.eye_dome = a.eye_dome;
    job.render.fog_distance = a.fog;
    job.render.shading = a.shading;
    job.output = "view.png";  // validate()'s one-image mode; nothing is written
    if (const auto problems = job.validate(); !problems.empty()) {
        std::string msg = problems.front();
        for (std::size_t i = 1; i < problems.size(); ++i) {
            msg += "; " + problems[i];
        }
        throw ConfigError(msg);
    }
    return job;
}

/// The frame run_view_frames renders for one pose (job.pose, or the overview of all the data).
ViewImage view_image(const ViewJobConfig& job, std::vector<std::string>& warnings) {
    ViewCamera camera = job.camera;
    if (job.pose) {
        camera.set_pose(*job.pose);
        camera.validate();
    }
    ViewSession session(job.inputs, job.session);
    warnings = session.sources().warnings();
    if (!job.pose) {
        const PointsBox box = points_box(session.sources());
        camera.set_pose(overview_camera(box.lo, box.hi, job.camera).pose());
    }
    const IngestStats stats = session.move_to(camera.position);
    warnings.insert(warnings.end(), stats.warnings.begin(), stats.warnings.end());
    return session.render(camera, job.render);
}

py::array view(std::vector<std::filesystem::path> files, const ViewArgs& args) {
    const ViewJobConfig job = view_job(std::move(files), args);
    std::vector<std::string> warnings;
    ViewImage image;
    {
        py::gil_scoped_release release;
        image = view_image(job, warnings);
    }
    for (const auto& w : warnings) {  // the CLI's "beamtrace: warning: ..." lines
        if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) {
            throw py::error_already_set();
        }
    }
    return to_numpy(std::move(image.rgb), {image.height, image.width, 3});
}

/// `files`: one path, or a sequence of them.
std::vector<std::filesystem::path> file_list(const py::object& files) {
    if (py::isinstance<py::str>(files) || py::hasattr(files, "__fspath__")) {
        return {files.cast<std::filesystem::path>()};
    }
    return files.cast<std::vector<std::filesystem::path>>();
}

}  // namespace

void bind_view(py::module_& m) {
    const ViewJobConfig d;
    const HeightFieldConfig& f = d.session.field;
    m.def(
        "view",
        [](const py::object& files, py::object camera, std::pair<int, int> size, double fov_deg,
           double cell_size, int levels, int section_cells, int sections, py::object memory_budget,
           std::string color, int height_stacks, double stack_gap, int fill_gaps, double eye_dome,
           double fog, bool shading, unsigned threads) {
            return view(
                file_list(files),
                ViewArgs{std::move(camera), size, fov_deg, cell_size, levels, section_cells,
                         sections, std::move(memory_budget), std::move(color), height_stacks,
                         stack_gap, fill_gaps, eye_dome, fog, shading, threads});
        },
        py::arg("files"), py::kw_only(), py::arg("camera") = py::none(),
        py::arg("size") = std::make_pair(d.camera.width, d.camera.height),
        py::arg("fov_deg") = d.camera.hfov_deg, py::arg("cell_size") = f.cell_size,
        py::arg("levels") = f.levels, py::arg("section_cells") = f.section_cells,
        py::arg("sections") = f.sections, py::arg("memory_budget") = f.memory_budget_bytes,
        py::arg("color") = std::string(color_mode_name(f.color)),
        py::arg("height_stacks") = f.height_stacks, py::arg("stack_gap") = f.stack_gap,
        py::arg("fill_gaps") = f.gap_fill_cells, py::arg("eye_dome") = d.render.eye_dome,
        py::arg("fog") = d.render.fog_distance, py::arg("shading") = d.render.shading,
        py::arg("threads") = d.session.threads,
        "`beamtrace view FILES --output v.png` in memory: the height-field view of LAS files as "
        "an (height, width, 3) uint8 array (docs/python.md).");
}

}  // namespace beamtrace::python
