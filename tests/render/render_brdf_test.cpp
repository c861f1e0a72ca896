// RenderConfig::brdf (render --brdf): the default phenomenological lobe of seed 003, or the
// energy-conserving normalised Phong lobe the surveys use; Lambertian materials render the same
// in both.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "beamtrace/render/renderer.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

RenderImage shiny_sphere(double s, Brdf brdf) {
    RenderScene rs;
    rs.materials = {Material{"shiny", 0.8, s, 200.0, {}, {}}};
    rs.spheres.push_back({{{0, 0, 0}, 1.0}, {}, 0, 0});
    RenderConfig cfg;
    cfg.camera.projection = Projection::orthographic;
    cfg.camera.position_m = {0, 0, 10};
    cfg.camera.orientation = {0, -kPi / 2, 0};
    cfg.camera.view_width_m = 2.2;
    cfg.camera.width = cfg.camera.height = 121;
    cfg.ambient = 0;
    cfg.lights = {directional_light(0.0, kPi / 3)};
    cfg.brdf = brdf;
    ThreadPool pool(2);
    return Renderer(rs, pool).render(cfg);
}

TEST(RenderBrdf, DefaultIsPhenomenologicalAndLambertianIsTheSame) {
    EXPECT_EQ(RenderConfig{}.brdf, Brdf::phenomenological);
    EXPECT_EQ(shiny_sphere(0.0, Brdf::phenomenological).radiance,
              shiny_sphere(0.0, Brdf::normalized_phong).radiance);
}

TEST(RenderBrdf, NormalizedPhongHighlightIsBrighter) {
    const auto seed = shiny_sphere(0.5, Brdf::phenomenological).radiance;
    const auto phong = shiny_sphere(0.5, Brdf::normalized_phong).radiance;
    const float seed_peak = *std::max_element(seed.begin(), seed.end());
    const float phong_peak = *std::max_element(phong.begin(), phong.end());
    // At the mirror pixel (cos i = cos 30 deg): seed 0.8 (0.5 + 0.5 cos i) < 1; normalised
    // Phong 0.8 (0.5 + 0.5 * 101) cos i, about 35.
    EXPECT_LT(seed_peak, 1.0f);
    EXPECT_GT(phong_peak, 20.0f);
    EXPECT_NE(seed, phong);
}

}  // namespace
}  // namespace beamtrace
