// Analytic truths of the renderer: sphere volume from orthographic chords, the elliptic shadow
// of a sphere, Lambert's cosine, the specular mirror peak, inverse-square point lights,
// occlusion between objects, determinism across thread counts.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "beamtrace/core/error.hpp"
#include "beamtrace/geometry/primitives.hpp"
#include "beamtrace/pipeline/render_job.hpp"
#include "beamtrace/render/render_options.hpp"
#include "beamtrace/render/renderer.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

/// An orthographic camera 10 m above the origin looking straight down (+y is image left).
CameraConfig top_view(double width_m, int pixels) {
    CameraConfig c;
    c.projection = Projection::orthographic;
    c.position_m = {0, 0, 10};
    c.orientation = {0, -kPi / 2, 0};
    c.view_width_m = width_m;
    c.width = c.height = pixels;
    return c;
}

RenderScene plane_scene(double reflectance = 1.0, double s = 0.0, double n = 10.0) {
    RenderScene rs;
    rs.materials = {Material{"m", reflectance, s, n, {}, {}}};
    rs.planes.push_back(
        {make_plane_patch({0, 0, 0}, {0, 0, 1}, std::numeric_limits<double>::infinity()), 0, 0});
    return rs;
}

TEST(RenderGeometry, SphereIntersectionAndChord) {
    const Sphere s{{0, 0, 5}, 2};
    const auto iv = intersect_sphere_line({0, 0, 0}, {0, 0, 1}, s);
    ASSERT_TRUE(iv);
    EXPECT_DOUBLE_EQ(iv->t_enter, 3.0);
    EXPECT_DOUBLE_EQ(iv->t_exit, 7.0);
    EXPECT_DOUBLE_EQ(sphere_chord({0, 0, 0}, {0, 0, 1}, s, 0, 1e9), 4.0);
    EXPECT_DOUBLE_EQ(sphere_chord({0, 0, 5}, {0, 0, 1}, s, 0, 1e9), 2.0);  // from inside
    EXPECT_NEAR(sphere_chord({1, 0, 0}, {0, 0, 1}, s, 0, 1e9), 2 * std::sqrt(3.0), 1e-12);
    EXPECT_FALSE(intersect_sphere_line({3, 0, 0}, {0, 0, 1}, s));
    EXPECT_EQ(*intersect_sphere({0, 0, 5}, {0, 0, 1}, s, 0, 1e9), 2.0);
    // A plane patch is exactly make_square's square.
    const PlanePatch p = make_plane_patch({1, 2, 3}, {0, 1, 1}, 4);
    const TriangleMesh sq = make_square({1, 2, 3}, {0, 1, 1}, 4);
    for (const auto& v : sq.vertices) {
        const Vec3d r = Vec3d(v) - p.point_m;
        EXPECT_NEAR(std::fabs(dot(r, p.u_axis)), 2.0, 1e-5);
        EXPECT_NEAR(std::fabs(dot(r, p.w_axis())), 2.0, 1e-5);
    }
    EXPECT_TRUE(intersect_plane({1, 2, 10}, {0, 0, -1}, p, 0, 1e9));
    EXPECT_FALSE(intersect_plane({1, 8, 10}, {0, 0, -1}, p, 0, 1e9));
}

TEST(RenderSphere, OrthographicChordsSumToVolume) {
    RenderScene rs;
    rs.spheres.push_back({{{0.3, -0.2, 1.0}, 1.0}, {}, 0, 0});
    ThreadPool pool(2);
    const Renderer r(rs, pool);
    const CameraConfig cam = top_view(3.0, 240);  // the whole sphere in view
    const auto chords = r.thickness(cam);
    double sum = 0;
    for (double c : chords) {
        sum += c;
    }
    const double volume = sum * Camera(cam).pixel_area_m2();
    EXPECT_NEAR(volume / (4.0 / 3.0 * kPi), 1.0, 0.005);
}

TEST(RenderSphere, ClosedMeshThicknessAlsoGivesVolume) {
    // An icosphere through the backend (back minus front ranges) gives its own volume, a bit
    // below the sphere's.
    RenderScene rs;
    rs.add_mesh(make_icosphere({0, 0, 1}, 1.0, 4), 0, 0);
    ThreadPool pool(2);
    const Renderer r(rs, pool);
    const CameraConfig cam = top_view(2.4, 200);
    double sum = 0;
    for (double c : r.thickness(cam)) {
        sum += c;
    }
    const double ratio = sum * Camera(cam).pixel_area_m2() / (4.0 / 3.0 * kPi);
    EXPECT_GT(ratio, 0.98);
    EXPECT_LT(ratio, 1.005);
}

TEST(RenderShadow, SphereShadowOnPlaneIsTheAnalyticEllipse) {
    RenderScene rs = plane_scene(0.8);
    const Vec3d c{0.5, 0.2, 1.2};
    const double radius = 0.5;
    rs.spheres.push_back({{c, radius}, {}, 0, 1});
    const double az = 0.6, el = 0.7;
    RenderConfig cfg;
    cfg.camera = top_view(6.0, 200);
    cfg.ambient = 0.0;
    cfg.lights = {directional_light(az, el)};
    ThreadPool pool(2);
    const RenderImage img = Renderer(rs, pool).render(cfg);
    // Shadow on z = 0: centre c_xy - (c_z / tan el) (cos az, sin az); semi-axes r / sin el along
    // the light's azimuth and r across it.
    const Vec3d a_hat{std::cos(az), std::sin(az), 0}, b_hat{-std::sin(az), std::cos(az), 0};
    const Vec3d centre = Vec3d{c.x, c.y, 0} - a_hat * (c.z / std::tan(el));
    const double sa = radius / std::sin(el), sb = radius;
    const auto in_shadow = [&](const Vec3d& q) {
        const double x = dot(q - centre, a_hat) / sa, y = dot(q - centre, b_hat) / sb;
        return x * x + y * y < 1.0;
    };
    const Camera cam(cfg.camera);
    const double px = 6.0 / 200;
    int checked = 0, shadowed = 0, mismatched = 0;
    for (int row = 0; row < img.height; ++row) {
        for (int col = 0; col < img.width; ++col) {
            if (img.part[img.index(col, row)] != 0) {
                continue;  // the sphere, not the plane
            }
            Vec3d o, d;
            cam.pixel_ray(col, row, o, d);
            const Vec3d q = o + d * (o.z / -d.z);
            const bool expect = in_shadow(q);
            bool near_edge = false;  // the outline passes within ~1 pixel
            for (double dx : {-1.0, 1.0}) {
                for (double dy : {-1.0, 1.0}) {
                    near_edge = near_edge || in_shadow(q + Vec3d{dx, dy, 0} * px) != expect;
                }
            }
            if (near_edge) {
                continue;
            }
            ++checked;
            shadowed += expect ? 1 : 0;
            const bool dark = img.at(col, row) < 1e-6f;
            mismatched += dark != expect ? 1 : 0;
        }
    }
    EXPECT_GT(checked, 30000);
    EXPECT_GT(shadowed, 500);
    EXPECT_EQ(mismatched, 0);
}

TEST(RenderShade, LambertianPlaneFollowsCosineOfIncidence) {
    const RenderScene rs = plane_scene(0.7);
    ThreadPool pool(2);
    const Renderer r(rs, pool);
    for (double theta : {0.0, 0.3, 0.8, 1.2, 1.5}) {
        RenderConfig cfg;
        cfg.camera = top_view(2.0, 8);
        cfg.ambient = 0.0;
        cfg.lights = {directional_light(0.4, kPi / 2 - theta, 2.0)};
        const RenderImage img = r.render(cfg);
        for (float v : img.radiance) {
            EXPECT_NEAR(v, 0.7 * 2.0 * std::cos(theta), 1e-6) << theta;
        }
    }
    // The light below the plane leaves its upper side dark (ambient only).
    RenderConfig cfg;
    cfg.camera = top_view(2.0, 4);
    cfg.ambient = 0.25;
    cfg.lights = {directional_light(0.0, -0.5)};
    for (float v : r.render(cfg).radiance) {
        EXPECT_NEAR(v, 0.7 * 0.25, 1e-7);
    }
}

TEST(RenderShade, SpecularPeakIsAtTheMirrorDirection) {
    EXPECT_DOUBLE_EQ(phenomenological_reflectance(0.6, 0.6, 2 * 0.36 - 1.0, 1.0, 50), 1.0);
    EXPECT_DOUBLE_EQ(phenomenological_reflectance(-0.1, 0.6, 0.0, 0.5, 5), 0.0);
    // A shiny sphere seen from above, lit from azimuth 0 at 60 degrees elevation: the brightest
    // pixel is where the normal is the half-vector of light and view.
    RenderScene rs;
    rs.materials = {Material{"shiny", 1.0, 1.0, 200.0, {}, {}}};
    rs.spheres.push_back({{{0, 0, 0}, 1.0}, {}, 0, 0});
    RenderConfig cfg;
    cfg.camera = top_view(2.2, 221);
    cfg.ambient = 0;
    cfg.lights = {directional_light(0.0, kPi / 3)};
    ThreadPool pool(2);
    const RenderImage img = Renderer(rs, pool).render(cfg);
    std::size_t best = 0;
    for (std::size_t i = 0; i < img.radiance.size(); ++i) {
        best = img.radiance[i] > img.radiance[best] ? i : best;
    }
    const Vec3d h = normalize(cfg.lights[0].direction + Vec3d{0, 0, 1});
    Vec3d o, d;
    Camera(cfg.camera).pixel_ray(static_cast<int>(best % 221), static_cast<int>(best / 221), o, d);
    EXPECT_NEAR(o.x, h.x, 0.015);
    EXPECT_NEAR(o.y, h.y, 0.015);
    EXPECT_GT(img.radiance[best], 0.99f);
}

TEST(RenderShade, PointLightFallsOffWithInverseSquare) {
    const RenderScene rs = plane_scene(0.5);
    ThreadPool pool(2);
    const Renderer r(rs, pool);
    RenderConfig cfg;
    cfg.camera = top_view(4.0, 5);  // the centre pixel looks at the origin
    cfg.ambient = 0;
    for (double hgt : {1.0, 2.0, 4.0}) {
        cfg.lights = {point_light({0, 0, hgt}, 8.0)};
        const RenderImage img = r.render(cfg);
        EXPECT_NEAR(img.at(2, 2), 0.5 * 8.0 / (hgt * hgt), 1e-6 * 8.0 / (hgt * hgt));
        // Off-nadir pixel: cos / r^2.
        Vec3d o, d;
        Camera(cfg.camera).pixel_ray(0, 2, o, d);
        const Vec3d q{o.x, o.y, 0};
        const double r2 = dot(q - Vec3d{0, 0, hgt}, q - Vec3d{0, 0, hgt});
        EXPECT_NEAR(img.at(0, 2), 0.5 * 8.0 * (hgt / std::sqrt(r2)) / r2, 1e-6);
    }
}

TEST(RenderOcclusion, NearestOfMeshAndExactPrimitivesWins) {
    RenderScene rs = plane_scene(0.5);
    rs.spheres.push_back({{{0, 0, 1}, 0.5}, {}, 0, 1});           // on the axis, below...
    rs.spheres.push_back({{{0, 0, 3}, 0.25}, {}, 0, 2});          // ...a smaller one
    rs.add_mesh(make_square({1.5, 0, 2}, {0, 0, 1}, 1.0), 0, 3);  // a triangle square above
    ThreadPool pool(2);
    RenderConfig cfg;
    cfg.camera = top_view(4.0, 40);                // 0.1 m pixels; centre between pixels 19 and 20
    cfg.lights = {directional_light(0, kPi / 2)};  // straight down
    const RenderImage img = Renderer(rs, pool).render(cfg);
    // Image left is +y, up is +x.
    const auto pixel_of = [](double x, double y) {
        return std::pair{static_cast<int>(20 - y / 0.1), static_cast<int>(20 - x / 0.1)};
    };
    const auto part_at = [&](double x, double y) {
        const auto [col, row] = pixel_of(x, y);
        return img.part[img.index(col, row)];
    };
    EXPECT_EQ(part_at(0.05, 0.05), 2);   // the small sphere hides the big one
    EXPECT_EQ(part_at(0.35, 0.05), 1);   // outside the small one
    EXPECT_EQ(part_at(1.55, 0.05), 3);   // the triangle square
    EXPECT_EQ(part_at(-1.55, 0.05), 0);  // the plane
    const auto [c, rw] = pixel_of(0.05, 0.05);
    EXPECT_NEAR(img.depth_m[img.index(c, rw)], 10 - 3 - std::sqrt(0.0625 - 0.005), 1e-5);
    // The square and the spheres cast shadows straight down onto the plane.
    const auto lit_plane = [&](double x, double y) {
        const auto [col, row] = pixel_of(x, y);
        return img.at(col, row);
    };
    EXPECT_NEAR(lit_plane(-1.55, 0.05), 0.5 * 1.1, 1e-6);
    cfg.camera.position_m = {0, 0, 1.2};  // below the square and the small sphere: see the shadows
    cfg.camera.view_width_m = 4.0;
    const RenderImage under = Renderer(rs, pool).render(cfg);
    const auto [col1, row1] = pixel_of(1.55, 0.05);
    EXPECT_NEAR(under.at(col1, row1), 0.5 * 0.1, 1e-6);  // the mesh square's shadow
    const auto [col2, row2] = pixel_of(-1.55, 0.05);
    EXPECT_NEAR(under.at(col2, row2), 0.5 * 1.1, 1e-6);
}

TEST(RenderShade, DeterministicAcrossThreadCountsAndBatches) {
    const auto spec =
        load_scene_spec(std::filesystem::path(BEAMTRACE_EXAMPLES_DIR) / "scenes/beach_ball.yaml");
    const Scene scene = build_scene(spec);
    const RenderScene rs = build_render_scene(scene);
    ASSERT_EQ(rs.spheres.size(), 1u);
    ASSERT_EQ(rs.planes.size(), 1u);
    EXPECT_TRUE(rs.mesh.faces.empty());
    RenderConfig cfg;
    cfg.camera.width = 96;
    cfg.camera.height = 64;
    cfg.camera.position_m = {-6, -4, 3};
    cfg.camera.orientation = look_at(cfg.camera.position_m, {0, 0, 0.8});
    cfg.lights = {directional_light(-1.0, 0.8), point_light({2, -2, 4}, 10)};
    ThreadPool one(1), three(3);
    const RenderImage a = Renderer(rs, one).render(cfg);
    cfg.batch_pixels = 1000;
    const RenderImage b = Renderer(rs, three).render(cfg);
    EXPECT_EQ(a.radiance, b.radiance);
    EXPECT_EQ(a.part, b.part);
    // The stripes show: the ball has two albedos.
    float lo = 1e9f, hi = 0;
    for (std::size_t i = 0; i < a.radiance.size(); ++i) {
        if (a.part[i] == 0) {
            lo = std::min(lo, a.radiance[i]);
            hi = std::max(hi, a.radiance[i]);
        }
    }
    EXPECT_GT(hi, 3 * lo);
    // Triangles instead of exact primitives give nearly the same picture.
    const RenderScene tri = build_render_scene(scene, false);
    EXPECT_TRUE(tri.spheres.empty());
    EXPECT_FALSE(tri.mesh.faces.empty());
}

TEST(RenderScene, SceneFileKeepsExactSpheresPlanesAndPatterns) {
    const std::string yaml = R"(
materials:
  - {name: ball, reflectance: 0.8, pattern: {kind: stripes, count: 6, reflectance: 0.2}}
parts:
  - sphere: {center_m: [1, 0, 0], radius_m: 0.5}
    transform: {translate_m: [0, 0, 2], scale: 2}
    material: ball
  - sphere: {center_m: [0, 0, 0], radius_m: 1}
    transform: {scale: [1, 2, 1]}
  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 10}
    transform: {rotate_deg: [0, 0, 90]}
)";
    const Scene scene = build_scene(parse_scene_spec(yaml, "mem.yaml"));
    ASSERT_EQ(scene.spheres.size(), 1u);  // the stretched sphere stays triangles only
    EXPECT_EQ(scene.spheres[0].center_m, (Vec3d{2, 0, 2}));
    EXPECT_DOUBLE_EQ(scene.spheres[0].radius_m, 1.0);
    ASSERT_EQ(scene.planes.size(), 1u);
    EXPECT_EQ(scene.planes[0].part, 2u);
    EXPECT_EQ(scene.materials[1].pattern.kind, AlbedoPatternKind::stripes);
    EXPECT_EQ(scene.materials[1].pattern.count, 6);
    const RenderScene rs = build_render_scene(scene);
    EXPECT_EQ(rs.mesh.faces.size(), scene.parts[1].face_count);
    EXPECT_EQ(rs.face_part.front(), 1u);
    // The rotated square's exact corners are the triangulated ones.
    const PlanePatch& p = rs.planes[0].plane;
    for (std::uint32_t f = scene.parts[2].first_face; f < scene.parts[2].first_face + 2; ++f) {
        for (const Vec3d& corner : scene.geometry.triangle(f)) {
            const Vec3d r = corner - p.point_m;
            EXPECT_NEAR(std::fabs(dot(r, p.u_axis)), 5.0, 1e-5);
            EXPECT_NEAR(std::fabs(dot(r, p.w_axis())), 5.0, 1e-5);
        }
    }
    EXPECT_THROW(
        static_cast<void>(parse_scene_spec(
            "materials: [{name: a, pattern: {kind: spots}}]\nparts: [{sphere: {}}]\n", "bad.yaml")),
        ConfigError);
}

TEST(RenderOptions, ParsesAndRejects) {
    const Light d = parse_light("dir:90,0,2");
    EXPECT_NEAR(d.direction.y, 1.0, 1e-12);
    EXPECT_EQ(d.intensity, 2.0);
    const Light p = parse_light("point:1,2,3");
    EXPECT_EQ(p.kind, LightKind::point);
    EXPECT_EQ(p.position_m, (Vec3d{1, 2, 3}));
    EXPECT_EQ(parse_image_size("64x48"), (std::pair{64, 48}));
    for (const char* bad : {"dir:1", "spot:1,2,3", "point:1,2", "dir:a,b", "dir:1,2,-1"}) {
        EXPECT_THROW(static_cast<void>(parse_light(bad)), ConfigError) << bad;
    }
    for (const char* bad : {"64", "0x5", "64x", "ax5", "64x48x2"}) {
        EXPECT_THROW(static_cast<void>(parse_image_size(bad)), ConfigError) << bad;
    }
    RenderJobConfig job;
    job.set_camera("1,2,3,90,10,30");
    EXPECT_NEAR(job.render.camera.vfov_rad, kPi / 6, 1e-12);
    EXPECT_NEAR(job.render.camera.orientation.yaw_rad, kPi / 2, 1e-12);
    EXPECT_NEAR(job.render.camera.orientation.pitch_rad, kPi / 18, 1e-12);
    EXPECT_EQ(*job.camera_position_m, (Vec3d{1, 2, 3}));
    EXPECT_TRUE(job.camera_angles);
    EXPECT_THROW(job.set_camera("1,2"), ConfigError);
    EXPECT_THROW(job.set_camera("1,2,3,4"), ConfigError);
    EXPECT_THROW(job.set_camera("1,2,3,4,5,200"), ConfigError);
    CameraConfig cam = job.render.camera;
    // look_at agrees with the camera's forward axis.
    cam.orientation = look_at({1, 2, 3}, {4, -2, 3 + 5});
    const Vec3d f = Camera(cam).forward();
    EXPECT_NEAR(dot(f, normalize(Vec3d{3, -4, 5})), 1.0, 1e-12);
    cam.width = 0;
    EXPECT_THROW(Camera{cam}, ConfigError);
}

TEST(RenderCli, WritesPngAndRejectsBadOptions) {
    test::TempDir dir;
    const std::string cli = BEAMTRACE_CLI_PATH;
    const std::string scene =
        (std::filesystem::path(BEAMTRACE_EXAMPLES_DIR) / "scenes/beach_ball.yaml").string();
    const auto png = dir / "ball.png";
    auto r = test::run_command(cli + " render " + scene +
                               " --size 48x32 --light dir:-60,45 --light point:2,2,3,5 --output " +
                               png.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(test::read_file(png).substr(1, 3), "PNG");
    r = test::run_command(cli + " render --demo --size 40x20 --quiet --output " +
                          (dir / "demo.png").string());
    EXPECT_EQ(r.exit_code, 0) << r.out;
    for (const std::string bad :
         {"--size 0x5", "--light spot:1,2", "--camera 1,2", "--orthographic -1", "--zoom 0"}) {
        r = test::run_command(cli + " render " + scene + " " + bad + " --output " +
                              (dir / "bad.png").string());
        EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.png"));
    EXPECT_EQ(test::entry_count(dir.path()), 2u);
}

TEST(RenderCli, LookAtNeedsOnlyThePosition) {
    test::TempDir dir;
    const std::string cli =
        std::string(BEAMTRACE_CLI_PATH) + " render " +
        (std::filesystem::path(BEAMTRACE_EXAMPLES_DIR) / "scenes/beach_ball.yaml").string() +
        " --size 48x32 --quiet --look-at 0,0,0.8 ";
    auto r = test::run_command(cli + "--camera -6,-4,3 --output " + (dir / "a.png").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    r = test::run_command(cli + "--camera -6,-4,3,10,20 --output " + (dir / "b.png").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(test::read_file(dir / "a.png"), test::read_file(dir / "b.png"));
    // X,Y,Z alone is a position without a direction: it needs --look-at.
    r = test::run_command(std::string(BEAMTRACE_CLI_PATH) + " render --demo --camera -6,-4,3 " +
                          "--output " + (dir / "c.png").string());
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find("needs --look-at"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "c.png"));
}

}  // namespace
}  // namespace beamtrace
