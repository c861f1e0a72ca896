// Sphere parts with `exact: true`: one face ID per copy, placed by the part's transform and
// array, traced as spheres, kept for the renderer, and refused with the key where they cannot be.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/render/render_scene.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(SceneExactSphere, PartsGetOneFacePerCopyBetweenTriangleParts) {
    const SceneSpec spec = parse_scene_spec(R"(parts:
  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 100}
  - sphere: {center_m: [1, 0, 0], radius_m: 2, exact: true}
    name: ball
    transform: {translate_m: [0, 0, 10], rotate_deg: [0, 0, 90], scale: 1.5}
    label: 9
  - sphere: {center_m: [0, 0, 1], radius_m: 1, exact: true}
    name: row
    array: {count: [3, 1, 1], step_m: [10, 0, 0]}
  - sphere: {center_m: [0, 30, 2], radius_m: 2, subdivisions: 1}
)",
                                            "scene.yaml");
    const Scene s = build_scene(spec);
    ASSERT_EQ(s.parts.size(), 4u);
    EXPECT_EQ(s.parts[1].first_face, 2u);
    EXPECT_EQ(s.parts[1].face_count, 1u);
    EXPECT_EQ(s.parts[2].first_face, 3u);
    EXPECT_EQ(s.parts[2].face_count, 3u);
    EXPECT_EQ(s.parts[2].instance_count, 3u);
    EXPECT_EQ(s.parts[3].first_face, 6u);
    EXPECT_EQ(s.triangle_count(), 2u + 80u);
    EXPECT_EQ(s.sphere_count(), 4u);
    EXPECT_EQ(s.geometry.face_count(), 86u);
    // The part's transform places the centre (1, 0, 0) as it places a mesh's vertices: turned a
    // quarter about z and scaled by 1.5.
    const ExactSphere* ball = s.geometry.sphere_of_face(2);
    ASSERT_NE(ball, nullptr);
    const Vec3d c = spec.parts[1].transform.apply({1, 0, 0});
    EXPECT_NEAR(ball->center.x, c.x, 1e-6);
    EXPECT_NEAR(ball->center.y, c.y, 1e-6);
    EXPECT_NEAR(ball->center.z, 10.0f, 1e-6f);
    EXPECT_NEAR(std::fabs(c.y), 1.5, 1e-12);
    EXPECT_FLOAT_EQ(ball->radius, 3.0f);
    EXPECT_FLOAT_EQ(s.geometry.sphere_of_face(5)->center.x, 20.0f);

    ThreadPool pool(1);
    RayBatch rays;
    rays.push_back({0, c.y, 50}, {0, 0, -1});  // the ball's top at z = 13: 37 m
    rays.push_back({20, 0, 50}, {0, 0, -1});   // the third copy of the row, top at z = 2: 48 m
    rays.push_back({5, 0, 50}, {0, 0, -1});    // between the copies: the plane at 50 m
    rays.push_back({0, 30, 50}, {0, 0, -1});   // the icosphere (a vertex at its top): 46 m
    for (const BackendKind kind : test::backends()) {
        const HitBatch h = make_backend(kind, s.geometry, pool)->intersect(rays, pool);
        const std::string k(to_string(kind));
        EXPECT_EQ(h.face[0], 2u) << k;
        EXPECT_NEAR(h.t[0], 37.0f, 1e-5f) << k;
        EXPECT_EQ(h.face[1], 5u) << k;
        EXPECT_EQ(s.parts[s.part_of_face(h.face[1])].name, "row") << k;
        EXPECT_NEAR(h.t[1], 48.0f, 1e-5f) << k;
        EXPECT_LT(h.face[2], 2u) << k;
        EXPECT_NEAR(h.t[2], 50.0f, 1e-5f) << k;
        EXPECT_EQ(s.part_of_face(h.face[3]), 3u) << k;
        EXPECT_NEAR(h.t[3], 46.0f, 1e-4f) << k;
    }

    // The renderer gets the exact spheres as spheres, with or without analytic primitives, and
    // no triangles for them.
    for (const bool analytic : {true, false}) {
        const RenderScene rs = build_render_scene(s, analytic);
        EXPECT_EQ(rs.spheres.size(), analytic ? 5u : 4u) << analytic;
        EXPECT_EQ(rs.mesh.faces.size(), analytic ? 0u : 82u) << analytic;
    }
}

TEST(SceneExactSphere, ImpossibleExactSpheresNameTheKey) {
    try {
        (void)parse_scene_spec(R"(parts:
  - sphere: {radius_m: 1, exact: true, subdivisions: 3}
  - sphere: {radius_m: 1, exact: true}
    transform: {scale: [1, 2, 1]}
  - sphere: {radius_m: 1, exact: sometimes}
)",
                               "bad.yaml");
        FAIL() << "expected a ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("bad.yaml:2: parts[0].sphere.subdivisions: an exact sphere has no "
                           "subdivisions"),
                  std::string::npos)
            << msg;
        EXPECT_NE(msg.find("bad.yaml:4: parts[1].transform.scale: an exact sphere needs the same "
                           "scale on every axis"),
                  std::string::npos)
            << msg;
        EXPECT_NE(msg.find("bad.yaml:5: parts[2].sphere.exact: expected true or false"),
                  std::string::npos)
            << msg;
    }
}

}  // namespace
}  // namespace beamtrace
