// `beamtrace render` as one library call: the settings the CLI binds its options to (declared
// once here, with their defaults), the camera and light the scene gets when none is given, and
// the run that loads the scene, renders it and writes the PNG (docs/render.md).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/camera_pose.hpp"
#include "beamtrace/core/vec3.hpp"
#include "beamtrace/render/render_scene.hpp"
#include "beamtrace/render/renderer.hpp"

namespace beamtrace {

struct RenderJobConfig {
    std::filesystem::path scene;  ///< scene file (YAML, docs/scene-file.md); empty with `demo`
    bool demo = false;            ///< render the embedded demo scene instead
    /// Camera (pinhole, 640x480 pixels, vfov 0.8 rad), lights (none: one directional light over
    /// the camera's left shoulder), ambient 0.1, background 0, shadows on.
    RenderConfig render;
    /// Where the camera is (docs/camera.md); none: frame the whole scene (the demo scene: the
    /// demo sensor's view). render.camera.orientation holds its yaw and pitch when
    /// `camera_angles`.
    std::optional<Vec3d> camera_position_m;
    bool camera_angles = false;      ///< the camera pose gave yaw and pitch
    std::optional<Vec3d> look_at_m;  ///< aim at this point (replaces yaw and pitch; keeps roll)
    double exposure = 1.0;           ///< radiance scale before clamping to [0, 1], > 0
    double gamma = 1.0;              ///< pixel = value^(1/gamma), > 0
    bool exact_primitives = true;    ///< trace sphere and plane parts exactly (not triangles)
    BackendKind backend = default_backend_kind();
    unsigned threads = 0;          ///< 0: every hardware thread
    std::filesystem::path output;  ///< PNG, written atomically

    /// Sets the camera from `X,Y,Z,YAW,PITCH[,VFOV]` (metres, degrees; VFOV in (0, 180)) or,
    /// to go with look_at_m, `X,Y,Z`. Throws ConfigError naming the text.
    void set_camera(std::string_view text);
    /// Sets look_at_m from `X,Y,Z` (metres); throws ConfigError naming the text.
    void set_look_at(std::string_view text);

    /// Every problem of these settings, in the order the CLI reports them; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// The camera and lights the job renders `scene` with: the pose of camera_position_m (aimed at
/// look_at_m when given), else the demo sensor's view (demo, pinhole) or frame_bounds; one
/// directional light 30 degrees left of the view direction and 50 degrees up when there is
/// none. Throws ConfigError.
[[nodiscard]] RenderConfig resolve_render_config(const RenderJobConfig& job,
                                                 const RenderScene& scene);

struct RenderJobResult {
    std::size_t triangles = 0, spheres = 0, planes = 0;
    int width = 0, height = 0;
    std::size_t lights = 0;
    double load_s = 0.0;    ///< scene load, backend build and thread start
    double render_s = 0.0;  ///< rendering
};

/// A job's image before it is written, and what the summary says of it.
struct RenderedJob {
    RenderImage image;  ///< radiance; to_rgb8(image, job.exposure, job.gamma) is the PNG's pixels
    RenderJobResult result;
};

/// Validates `job` (ConfigError with every problem), loads the scene and renders it; job.output
/// is not used. Throws ConfigError or InputError with context.
[[nodiscard]] RenderedJob render_job_image(const RenderJobConfig& job);

/// render_job_image, then the PNG written to job.output. Throws ConfigError, InputError or
/// OutputError with context.
[[nodiscard]] RenderJobResult run_render_job(const RenderJobConfig& job);

}  // namespace beamtrace
