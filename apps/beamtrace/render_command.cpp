// `beamtrace render`: a shaded image of a scene file or the demo scene.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"
#include "beamtrace/render/render_options.hpp"
#include "beamtrace/render/renderer.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "commands.hpp"

namespace beamtrace::cli {
namespace {

struct RenderOptions {
    std::string scene;
    bool demo = false;
    std::string camera, look_at, size = "640x480";
    std::optional<double> roll_deg, zoom, orthographic_m;
    std::vector<std::string> lights;
    double ambient = 0.1, background = 0.0, exposure = 1.0, gamma = 1.0;
    bool no_shadows = false, triangles = false, quiet = false;
    std::string backend{to_string(default_backend_kind())};
    unsigned threads = 0;
    std::string output;
};

int run(const RenderOptions& o) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    if (o.demo == !o.scene.empty()) {
        throw ConfigError("give exactly one of SCENE.yaml or --demo");
    }
    RenderConfig config;
    CameraConfig& cam = config.camera;
    const auto [w, h] = parse_image_size(o.size);
    cam.width = w;
    cam.height = h;
    if (o.orthographic_m) {
        cam.projection = Projection::orthographic;
        cam.view_width_m = *o.orthographic_m;
    }
    if (o.zoom) {
        cam.zoom = *o.zoom;
    }
    constexpr double kDeg = std::numbers::pi / 180.0;
    if (o.roll_deg) {
        cam.orientation.roll_rad = *o.roll_deg * kDeg;
    }
    for (const auto& l : o.lights) {
        config.lights.push_back(parse_light(l));
    }
    if (!o.camera.empty()) {
        parse_camera_pose(o.camera, cam);
    }
    if (!o.look_at.empty()) {
        if (o.camera.empty()) {
            throw ConfigError("--look-at needs --camera for the position");
        }
        const std::string text = o.look_at + ",0,0";  // reuse the pose parser for X,Y,Z
        CameraConfig target;
        try {
            parse_camera_pose(text, target);
        } catch (const ConfigError&) {
            throw ConfigError("--look-at '" + o.look_at + "': expected X,Y,Z in metres");
        }
        cam.orientation = look_at(cam.position_m, target.position_m, cam.orientation.roll_rad);
    }
    config.ambient = o.ambient;
    config.background = o.background;
    config.shadows = !o.no_shadows;
    if (!(o.ambient >= 0.0) || !(o.background >= 0.0)) {
        throw ConfigError("--ambient and --background must not be negative");
    }
    if (!(o.exposure > 0.0) || !(o.gamma > 0.0)) {
        throw ConfigError("--exposure and --gamma must be positive");
    }
    if (const auto problems = cam.validate(); !problems.empty()) {
        throw ConfigError("camera: " + problems.front());
    }
    const BackendKind backend = parse_backend_kind(o.backend);

    const Scene scene = o.demo ? make_demo_scene() : load_scene_file(o.scene);
    const RenderScene rs = build_render_scene(scene, !o.triangles);
    if (o.camera.empty()) {
        if (o.demo && cam.projection == Projection::pinhole) {
            const ImageSensorConfig s = demo_sensor();
            cam.position_m = s.position_m;
            cam.orientation = s.orientation;
            cam.vfov_rad = s.vfov_rad;
        } else {
            cam = frame_bounds(rs.bounds(), cam);
        }
    }
    if (config.lights.empty()) {
        // Over the camera's left shoulder: 30 degrees left of the view direction, 50 up.
        const Vec3d f = Camera(cam).forward();
        config.lights.push_back(
            directional_light(std::atan2(-f.y, -f.x) - 30.0 * kDeg, 50.0 * kDeg));
    }
    ThreadPool pool(o.threads);
    const auto t1 = clock::now();
    const Renderer renderer(rs, pool, backend);
    const RenderImage image = renderer.render(config);
    const auto t2 = clock::now();
    write_render_png(o.output, image, o.exposure, o.gamma);
    if (!o.quiet) {
        const auto secs = [](auto a, auto b) {
            return std::chrono::duration<double>(b - a).count();
        };
        std::printf("scene: %zu triangles, %zu exact spheres, %zu exact planes\n",
                    rs.mesh.faces.size(), rs.spheres.size(), rs.planes.size());
        std::printf("image: %dx%d, %zu light(s), load %.3f s, render %.3f s\n", image.width,
                    image.height, config.lights.size(), secs(t0, t1), secs(t1, t2));
        std::printf("wrote %s\n", o.output.c_str());
    }
    return 0;
}

}  // namespace

std::function<int()> add_render_command(CLI::App& app) {
    auto opts = std::make_shared<RenderOptions>();
    CLI::App* cmd = app.add_subcommand(
        "render", "Render a shaded image of a scene (lights, shadows, exact spheres and planes)");
    cmd->add_option("scene", opts->scene, "Scene file (YAML)")->check(CLI::ExistingFile);
    cmd->add_flag("--demo", opts->demo, "Render the embedded demo scene");
    cmd->add_option("--camera", opts->camera,
                    "Camera X,Y,Z,YAW,PITCH[,VFOV]: metres and degrees (yaw > 0 pans right, "
                    "pitch > 0 tilts up; default VFOV 45.8); default: frame the whole scene");
    cmd->add_option("--look-at", opts->look_at, "Aim the camera at X,Y,Z (overrides yaw, pitch)");
    cmd->add_option("--roll", opts->roll_deg, "Camera roll in degrees");
    cmd->add_option("--zoom", opts->zoom, "Magnification (divides the field of view or width)");
    cmd->add_option("--orthographic", opts->orthographic_m,
                    "Orthographic projection with this view width in metres");
    cmd->add_option("--size", opts->size, "Image size WIDTHxHEIGHT")->capture_default_str();
    cmd->add_option("--light", opts->lights,
                    "dir:AZ,EL[,E] (degrees; az counter-clockwise from +x) or point:X,Y,Z[,P] "
                    "(E = P/r^2); repeat for several; default: one directional light");
    cmd->add_option("--ambient", opts->ambient, "Ambient irradiance")->capture_default_str();
    cmd->add_option("--background", opts->background, "Radiance where rays miss")
        ->capture_default_str();
    cmd->add_option("--exposure", opts->exposure, "Radiance scale before clamping to [0, 1]")
        ->capture_default_str();
    cmd->add_option("--gamma", opts->gamma, "Output gamma (pixel = value^(1/gamma))")
        ->capture_default_str();
    cmd->add_flag("--no-shadows", opts->no_shadows, "Do not trace shadow rays");
    cmd->add_flag("--triangles", opts->triangles,
                  "Trace sphere and plane parts as their triangles instead of exactly");
    cmd->add_option("--backend", opts->backend, backend_choices())->capture_default_str();
    cmd->add_option("--threads", opts->threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    cmd->add_option("--output", opts->output, "Output PNG (written atomically)")->required();
    cmd->add_flag("--quiet", opts->quiet, "No summary");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
