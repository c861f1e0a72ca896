// Shaded images of a RenderScene: nearest hit of the backend's triangles and the exact spheres
// and planes, the reflectance of each material (RenderConfig::brdf) under directional and point
// lights, cast shadows from batched occlusion rays, and an ambient term.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/physics/material.hpp"
#include "beamtrace/render/camera.hpp"
#include "beamtrace/render/render_scene.hpp"
#include "beamtrace/render/shading.hpp"

namespace beamtrace {

struct RenderConfig {
    CameraConfig camera;
    std::vector<Light> lights;  ///< none: ambient light only
    double ambient = 0.1;       ///< ambient irradiance: every hit gets ambient * albedo
    double background = 0.0;    ///< radiance of pixels that see nothing
    /// Pixels that see nothing show a sky instead of `background`: radiance 1 coloured from a
    /// pale horizon (0.85, 0.9, 1) up to a blue zenith (0.3, 0.5, 0.9) by the ray's elevation.
    bool sky = false;
    bool shadows = true;  ///< trace occlusion rays towards every light
    /// The specular lobe's form (physics/material.hpp): the assignment's phenomenological one, or
    /// the energy-conserving normalised Phong BRDF.
    Brdf brdf = Brdf::phenomenological;
    /// Pixels traced per batch (bounds the memory of ray and hit batches); results do not depend
    /// on it.
    std::size_t batch_pixels = std::size_t{1} << 16;
};

/// Row-major images, (0, 0) at the top left.
struct RenderImage {
    int width = 0;
    int height = 0;
    std::vector<float> radiance;     ///< albedo * (ambient + sum of E * L); background on a miss
    std::vector<float> depth_m;      ///< distance along the pixel ray; +inf on a miss
    std::vector<std::int32_t> part;  ///< the scene part seen, -1 on a miss
    /// The colour (Material::color) of the surface seen, RGB, 3 per pixel; 1 on a miss. Empty:
    /// grey (to_rgb8).
    std::vector<float> color;

    [[nodiscard]] std::size_t index(int column, int row) const {
        return static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
               static_cast<std::size_t>(column);
    }
    [[nodiscard]] float at(int column, int row) const { return radiance[index(column, row)]; }
};

class Renderer {
  public:
    /// Builds the backend over `scene.mesh` (skipped when it has no triangles). `scene` and
    /// `pool` must outlive the renderer. Throws ConfigError for an inconsistent scene.
    Renderer(const RenderScene& scene, ThreadPool& pool,
             BackendKind backend = default_backend_kind());

    /// Renders one image. Throws ConfigError for a bad camera. Deterministic: the same for any
    /// thread count and batch size.
    [[nodiscard]] RenderImage render(const RenderConfig& config) const;

    /// Per pixel, the total length of the pixel ray inside the solids: chords through the exact
    /// spheres (exit - entry) plus, for closed outward-facing meshes, the sum of back-face minus
    /// front-face ranges. With an orthographic camera, the sum over pixels times
    /// Camera::pixel_area_m2() is the volume in view (the assignment's volume extra).
    [[nodiscard]] std::vector<double> thickness(const CameraConfig& camera) const;

  private:
    const RenderScene& scene_;
    ThreadPool& pool_;
    std::unique_ptr<Backend> backend_;
};

/// 8-bit RGB pixels of the radiance tinted by the colour: per channel c,
/// 255 * clamp(exposure * L * color_c, 0, 1)^(1 / gamma) (grey for white materials).
[[nodiscard]] std::vector<std::uint8_t> to_rgb8(const RenderImage& image, double exposure = 1.0,
                                                double gamma = 1.0);

/// to_rgb8 written as a PNG, atomically (throws OutputError).
void write_render_png(const std::filesystem::path& path, const RenderImage& image,
                      double exposure = 1.0, double gamma = 1.0);

}  // namespace beamtrace
