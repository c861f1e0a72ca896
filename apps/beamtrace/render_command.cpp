// `beamtrace render`: a shaded image of a scene file or the demo scene. The options bind to the
// fields of RenderJobConfig (render/render_job.hpp), which holds the defaults.
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "beamtrace/pipeline/render_job.hpp"
#include "beamtrace/render/render_options.hpp"
#include "commands.hpp"

namespace beamtrace::cli {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct RenderCommand {
    RenderJobConfig job;
    bool quiet = false;
};

int run(const RenderCommand& c) {
    const RenderJobResult r = run_render_job(c.job);
    if (!c.quiet) {
        std::printf("scene: %zu triangles, %zu exact spheres, %zu exact planes\n", r.triangles,
                    r.spheres, r.planes);
        std::printf("image: %dx%d, %zu light(s), load %.3f s, render %.3f s\n", r.width, r.height,
                    r.lights, r.load_s, r.render_s);
        std::printf("wrote %s\n", c.job.output.string().c_str());
    }
    return 0;
}

/// --camera, --look-at, --roll, --zoom, --orthographic, --size: render.camera and the pose.
void add_camera_options(CLI::App* cmd, RenderJobConfig& job) {
    CameraConfig& cam = job.render.camera;
    cmd->add_option_function<std::string>(
        "--camera", [&job](const std::string& s) { job.set_camera(s); },
        "Camera X,Y,Z,YAW,PITCH[,VFOV]: metres and degrees (docs/camera.md: yaw 0 looks along "
        "+x, yaw > 0 pans right, pitch > 0 tilts up; default VFOV 45.8), or X,Y,Z with "
        "--look-at; default: frame the whole scene");
    cmd->add_option_function<std::string>(
        "--look-at", [&job](const std::string& s) { job.set_look_at(s); },
        "Aim the camera at X,Y,Z (replaces yaw and pitch; --camera X,Y,Z is enough)");
    cmd->add_option_function<double>(
        "--roll", [&cam](double deg) { cam.orientation.roll_rad = deg * kDeg; },
        "Camera roll in degrees");
    cmd->add_option("--zoom", cam.zoom, "Magnification (divides the field of view or width)")
        ->capture_default_str();
    cmd->add_option_function<double>(
        "--orthographic",
        [&cam](double width_m) {
            cam.projection = Projection::orthographic;
            cam.view_width_m = width_m;
        },
        "Orthographic projection with this view width in metres");
    cmd->add_option_function<std::string>(
           "--size",
           [&cam](const std::string& s) { std::tie(cam.width, cam.height) = parse_image_size(s); },
           "Image size WIDTHxHEIGHT")
        ->default_str(std::to_string(cam.width) + "x" + std::to_string(cam.height));
}

/// --light, --ambient, --background, --exposure, --gamma, --no-shadows, --brdf.
void add_light_options(CLI::App* cmd, RenderJobConfig& job) {
    RenderConfig& r = job.render;
    cmd->add_option_function<std::vector<std::string>>(
        "--light",
        [&r](const std::vector<std::string>& texts) {
            for (const auto& t : texts) {
                r.lights.push_back(parse_light(t));
            }
        },
        "dir:AZ,EL[,E] (degrees; az counter-clockwise from +x) or point:X,Y,Z[,P] "
        "(E = P/r^2); repeat for several; default: one directional light");
    cmd->add_option("--ambient", r.ambient, "Ambient irradiance")->capture_default_str();
    cmd->add_flag("--sky", r.sky,
                  "Rays that miss see a sky (pale horizon to blue zenith) instead of --background");
    cmd->add_option("--background", r.background, "Radiance where rays miss")
        ->capture_default_str();
    cmd->add_option("--exposure", job.exposure, "Radiance scale before clamping to [0, 1]")
        ->capture_default_str();
    cmd->add_option("--gamma", job.gamma, "Output gamma (pixel = value^(1/gamma))")
        ->capture_default_str();
    cmd->add_flag_callback(
        "--no-shadows", [&r] { r.shadows = false; }, "Do not trace shadow rays");
    cmd->add_option_function<std::string>(
           "--brdf", [&r](const std::string& s) { r.brdf = parse_brdf(s); },
           "Specular lobe: " + brdf_choices() + " (docs/render.md)")
        ->default_str(std::string(to_string(r.brdf)));
}

}  // namespace

std::function<int()> add_render_command(CLI::App& app) {
    auto c = std::make_shared<RenderCommand>();
    RenderJobConfig& job = c->job;
    CLI::App* cmd = app.add_subcommand(
        "render", "Render a shaded image of a scene (lights, shadows, exact spheres and planes)");
    cmd->add_option("scene", job.scene, "Scene file (YAML)")->check(CLI::ExistingFile);
    cmd->add_flag("--demo", job.demo, "Render the embedded demo scene");
    add_camera_options(cmd, job);
    add_light_options(cmd, job);
    cmd->add_flag_callback(
        "--triangles", [&job] { job.exact_primitives = false; },
        "Trace sphere and plane parts as their triangles instead of exactly");
    cmd->add_option_function<std::string>(
           "--backend", [&job](const std::string& s) { job.backend = parse_backend_kind(s); },
           backend_choices())
        ->default_str(std::string(to_string(job.backend)));
    cmd->add_option("--threads", job.threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    cmd->add_option("--output", job.output, "Output PNG (written atomically)")->required();
    cmd->add_flag("--quiet", c->quiet, "No summary");
    return [c] { return run(*c); };
}

}  // namespace beamtrace::cli
