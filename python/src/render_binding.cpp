// beamtrace.render: `beamtrace render` as one call (RenderJobConfig, the CLI's settings and
// defaults), the image returned as an (h, w, 3) uint8 array instead of a PNG; the GIL released
// while it renders.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <optional>
#include <string>
#include <vector>

#include "beamtrace/pipeline/render_job.hpp"
#include "bindings.hpp"
#include "camera_text.hpp"
#include "numpy_arrays.hpp"

namespace beamtrace::python {
namespace {

/// What render() was given, besides the scene.
struct RenderArgs {
    std::pair<int, int> size;
    py::object camera, look_at;
    double exposure, gamma, ambient, background;
    bool shadows, sky, triangles;
    std::optional<std::string> backend;
    unsigned threads;
};

RenderJobConfig render_job(const std::string& scene, const RenderArgs& a) {
    RenderJobConfig job;
    job.demo = scene == "demo";
    if (!job.demo) {
        job.scene = scene;
    }
    job.render.camera.width = a.size.first;
    job.render.camera.height = a.size.second;
    if (!a.camera.is_none()) {
        job.set_camera(position_text(a.camera));
    }
    if (!a.look_at.is_none()) {
        job.set_look_at(position_text(a.look_at));
    }
    job.exposure = a.exposure;
    job.gamma = a.gamma;
    job.render.ambient = a.ambient;
    job.render.background = a.background;
    job.render.shadows = a.shadows;
    job.render.sky = a.sky;
    job.exact_primitives = !a.triangles;
    if (a.backend) {
        job.backend = parse_backend_kind(*a.backend);
    }
    job.threads = a.threads;
    return job;
}

py::array render(const std::string& scene, const RenderArgs& args) {
    const RenderJobConfig job = render_job(scene, args);
    std::vector<std::uint8_t> rgb;
    int width = 0, height = 0;
    {
        py::gil_scoped_release release;
        const RenderedJob rendered = render_job_image(job);
        width = rendered.image.width;
        height = rendered.image.height;
        rgb = to_rgb8(rendered.image, job.exposure, job.gamma);
    }
    return to_numpy(std::move(rgb), {height, width, 3});
}

}  // namespace

void bind_render(py::module_& m) {
    const RenderJobConfig defaults;
    const CameraConfig& cam = defaults.render.camera;
    m.def(
        "render",
        [](const std::filesystem::path& scene, std::pair<int, int> size, py::object camera,
           py::object look_at, double exposure, double gamma, double ambient, double background,
           bool shadows, bool sky, bool triangles, std::optional<std::string> backend,
           unsigned threads) {
            return render(scene.string(), RenderArgs{size, std::move(camera), std::move(look_at),
                                                     exposure, gamma, ambient, background, shadows,
                                                     sky, triangles, std::move(backend), threads});
        },
        py::arg("scene"), py::kw_only(), py::arg("size") = std::make_pair(cam.width, cam.height),
        py::arg("camera") = py::none(), py::arg("look_at") = py::none(),
        py::arg("exposure") = defaults.exposure, py::arg("gamma") = defaults.gamma,
        py::arg("ambient") = defaults.render.ambient,
        py::arg("background") = defaults.render.background,
        py::arg("shadows") = defaults.render.shadows, py::arg("sky") = defaults.render.sky,
        py::arg("triangles") = !defaults.exact_primitives, py::arg("backend") = py::none(),
        py::arg("threads") = defaults.threads,
        "`beamtrace render` in memory: the shaded image of a scene file (or \"demo\") as an "
        "(height, width, 3) uint8 array (docs/python.md).");
}

}  // namespace beamtrace::python
