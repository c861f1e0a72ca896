#include "beamtrace/pipeline/render_job.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <utility>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"
#include "beamtrace/render/render_options.hpp"
#include "beamtrace/scene/demo_scene.hpp"
#include "beamtrace/scene/scene_builder.hpp"

namespace beamtrace {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

/// The camera of a job with camera_position_m, before the scene is known.
CameraConfig posed_camera(const RenderJobConfig& job) {
    CameraConfig cam = job.render.camera;
    cam.position_m = *job.camera_position_m;
    if (job.look_at_m) {
        cam.orientation = look_at(cam.position_m, *job.look_at_m, cam.orientation.roll_rad);
    }
    return cam;
}

}  // namespace

void RenderJobConfig::set_camera(std::string_view text) {
    const std::string what = "--camera '" + std::string(text) + "'";
    std::string why;
    const auto parsed = try_parse_camera_pose(text, {.position_only = true, .max_extra = 1}, why);
    if (!parsed) {
        throw ConfigError(what + ": expected X,Y,Z,YAW,PITCH[,VFOV] (metres, degrees) or X,Y,Z " +
                          "with --look-at");
    }
    camera_position_m = parsed->pose.position;
    camera_angles = parsed->has_angles;
    if (camera_angles) {
        const RollPitchYaw rpy = parsed->pose.orientation(render.camera.orientation.roll_rad);
        render.camera.orientation.pitch_rad = rpy.pitch_rad;
        render.camera.orientation.yaw_rad = rpy.yaw_rad;
    }
    if (!parsed->extra.empty()) {
        const double vfov_deg = parsed->extra[0];
        if (!(vfov_deg > 0.0 && vfov_deg < 180.0)) {
            throw ConfigError(what + ": VFOV must be in (0, 180) degrees");
        }
        render.camera.vfov_rad = vfov_deg * kDeg;
    }
}

void RenderJobConfig::set_look_at(std::string_view text) {
    std::string why;
    const auto parsed = try_parse_camera_pose(text, {.position_only = true}, why);
    if (!parsed || parsed->has_angles) {
        throw ConfigError("--look-at '" + std::string(text) + "': expected X,Y,Z in metres");
    }
    look_at_m = parsed->pose.position;
}

std::vector<std::string> RenderJobConfig::validate() const {
    std::vector<std::string> problems;
    if (demo == !scene.empty()) {
        problems.emplace_back("give exactly one of SCENE.yaml or --demo");
    }
    if (look_at_m && !camera_position_m) {
        problems.emplace_back("--look-at needs --camera for the position");
    }
    if (camera_position_m && !camera_angles && !look_at_m) {
        problems.emplace_back("--camera X,Y,Z needs --look-at (or give X,Y,Z,YAW,PITCH)");
    }
    if (!(render.ambient >= 0.0) || !(render.background >= 0.0)) {
        problems.emplace_back("--ambient and --background must not be negative");
    }
    if (!(exposure > 0.0) || !(gamma > 0.0)) {
        problems.emplace_back("--exposure and --gamma must be positive");
    }
    for (const auto& p : render.camera.validate()) {
        problems.push_back("camera: " + p);
    }
    if (problems.empty() && camera_position_m && look_at_m &&
        !(length(*look_at_m - *camera_position_m) > 0.0)) {
        problems.emplace_back("look-at target must differ from the camera position");
    }
    return problems;
}

RenderConfig resolve_render_config(const RenderJobConfig& job, const RenderScene& scene) {
    RenderConfig config = job.render;
    CameraConfig& cam = config.camera;
    if (job.camera_position_m) {
        cam = posed_camera(job);
    } else if (job.demo && cam.projection == Projection::pinhole) {
        const ImageSensorConfig s = demo_sensor();
        cam.position_m = s.position_m;
        cam.orientation = s.orientation;
        cam.vfov_rad = s.vfov_rad;
    } else {
        cam = frame_bounds(scene.bounds(), cam);
    }
    if (config.lights.empty()) {
        // Over the camera's left shoulder: 30 degrees left of the view direction, 50 up.
        const Vec3d f = Camera(cam).forward();
        config.lights.push_back(
            directional_light(std::atan2(-f.y, -f.x) - 30.0 * kDeg, 50.0 * kDeg));
    }
    return config;
}

RenderedJob render_job_image(const RenderJobConfig& job) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    if (const auto problems = job.validate(); !problems.empty()) {
        std::string msg = problems.front();
        for (std::size_t i = 1; i < problems.size(); ++i) {
            msg += "; " + problems[i];
        }
        throw ConfigError(msg);
    }
    const Scene scene = job.demo ? make_demo_scene() : load_scene_file(job.scene);
    const RenderScene rs = build_render_scene(scene, job.exact_primitives);
    const RenderConfig config = resolve_render_config(job, rs);
    ThreadPool pool(job.threads);
    const auto t1 = clock::now();
    const Renderer renderer(rs, pool, job.backend);
    RenderImage image = renderer.render(config);
    const auto t2 = clock::now();
    const auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
    const RenderJobResult result{rs.mesh.faces.size(), rs.spheres.size(), rs.planes.size(),
                                 image.width,          image.height,      config.lights.size(),
                                 secs(t0, t1),         secs(t1, t2)};
    return {std::move(image), result};
}

RenderJobResult run_render_job(const RenderJobConfig& job) {
    const RenderedJob rendered = render_job_image(job);
    write_render_png(job.output, rendered.image, job.exposure, job.gamma);
    return rendered.result;
}

}  // namespace beamtrace
