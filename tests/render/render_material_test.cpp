// `render` shades with the physics Material: its pattern (the same evaluation as a survey's
// intensities) and its colour.
#include <gtest/gtest.h>

#include <limits>
#include <numbers>

#include "beamtrace/geometry/ray_plane.hpp"
#include "beamtrace/render/renderer.hpp"

namespace beamtrace {
namespace {

/// An orthographic camera 10 m above the origin looking straight down.
CameraConfig looking_down(double width_m, int pixels) {
    CameraConfig c;
    c.projection = Projection::orthographic;
    c.position_m = {0, 0, 10};
    c.orientation = {0, -std::numbers::pi / 2, 0};
    c.view_width_m = width_m;
    c.width = c.height = pixels;
    return c;
}

RenderScene floor_with(const Material& m) {
    RenderScene rs;
    rs.materials = {m};
    rs.planes.push_back(
        {make_plane_patch({0, 0, 0}, {0, 0, 1}, std::numeric_limits<double>::infinity()), 0, 0});
    return rs;
}

RenderImage render_floor(const Material& m) {
    RenderConfig cfg;
    cfg.camera = looking_down(6.0, 60);
    cfg.ambient = 0.0;
    cfg.lights = {directional_light(0.3, 1.2)};
    ThreadPool pool(2);
    const RenderScene rs = floor_with(m);
    return Renderer(rs, pool).render(cfg);
}

TEST(RenderMaterial, PatternIsThePhysicsAlbedoAtEachPixel) {
    Material m;
    m.reflectance = 0.8;
    m.pattern = {AlbedoPatternKind::checker, 8, 1.0, 0.2, {}};
    Material plain = m;
    plain.pattern = {};
    const RenderImage img = render_floor(m);
    const RenderImage ref = render_floor(plain);
    const Camera camera(looking_down(6.0, 60));
    const PlanePatch floor = floor_with(m).planes[0].plane;
    const PatternFrame frame = PatternFrame::plane(floor.point_m, floor.u_axis, floor.w_axis());
    int alternate = 0;
    for (int row = 0; row < img.height; ++row) {
        for (int col = 0; col < img.width; ++col) {
            Vec3d o, d;
            camera.pixel_ray(col, row, o, d);
            const Vec3d at = o + d * (-o.z / d.z);
            const double want = albedo(m, frame, at) / m.reflectance;
            ASSERT_GT(ref.at(col, row), 0.0F);
            EXPECT_NEAR(img.at(col, row) / ref.at(col, row), want, 1e-6) << col << " " << row;
            alternate += want < 1.0 ? 1 : 0;
        }
    }
    EXPECT_GT(alternate, img.width * img.height / 4);
    EXPECT_LT(alternate, 3 * img.width * img.height / 4);
}

TEST(RenderMaterial, ColourTintsEachChannel) {
    Material white;
    white.reflectance = 0.6;
    Material orange = white;
    orange.color = {1.0, 0.5, 0.0};
    const RenderImage grey_img = render_floor(white);
    const RenderImage tinted_img = render_floor(orange);
    EXPECT_EQ(grey_img.radiance, tinted_img.radiance);  // colour is not brightness
    const auto grey = to_rgb8(grey_img);
    const auto tinted = to_rgb8(tinted_img);
    ASSERT_EQ(grey.size(), tinted.size());
    for (std::size_t i = 0; i < grey.size(); i += 3) {
        EXPECT_EQ(grey[i], grey[i + 1]);
        EXPECT_EQ(grey[i], grey[i + 2]);
        EXPECT_EQ(tinted[i], grey[i]);
        EXPECT_NEAR(tinted[i + 1], 0.5 * grey[i + 1], 0.51);
        EXPECT_EQ(tinted[i + 2], 0);
    }
    EXPECT_GT(grey[0], 20);
    // An image without colours (built by hand) is grey.
    RenderImage bare = tinted_img;
    bare.color.clear();
    EXPECT_EQ(to_rgb8(bare), grey);
}

}  // namespace
}  // namespace beamtrace
