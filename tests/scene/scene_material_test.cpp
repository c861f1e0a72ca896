// Scene files hold physics Materials (the one material model): the same keys as before, a
// colour, and the surface each part's pattern is laid on.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "beamtrace/scene/scene_spec.hpp"

namespace beamtrace {
namespace {

TEST(SceneMaterial, ParsesEveryMaterialKeyIntoAPhysicsMaterial) {
    const SceneSpec s = parse_scene_spec(R"(
materials:
  - name: ball
    reflectance: 0.9
    specular_weight: 0.4
    specular_exponent: 40
    pattern: {kind: stripes, count: 6, size_m: 0.5, reflectance: 0.25}
    color: [1, 0.5, 0]
  - {name: lawn, library: grass, pattern: {kind: checker}}
  - {name: plain, pattern: {kind: none}}
parts:
  - {sphere: {}, material: ball}
)",
                                         "mem.yaml");
    ASSERT_EQ(s.materials.size(), 4u);
    const Material& ball = s.materials[1];
    EXPECT_EQ(ball.name, "ball");
    EXPECT_EQ(ball.reflectance, 0.9);
    EXPECT_EQ(ball.specular_weight, 0.4);
    EXPECT_EQ(ball.specular_exponent, 40.0);
    EXPECT_EQ(ball.pattern.kind, AlbedoPatternKind::stripes);
    EXPECT_EQ(ball.pattern.count, 6);
    EXPECT_EQ(ball.pattern.size_m, 0.5);
    EXPECT_EQ(ball.pattern.alternate_reflectance, 0.25);
    EXPECT_EQ(ball.color, (Vec3d{1, 0.5, 0}));
    EXPECT_TRUE(ball.library.empty());
    EXPECT_TRUE(ball.validate().empty());
    EXPECT_EQ(s.materials[2].library, "grass");
    EXPECT_EQ(s.materials[2].pattern.kind, AlbedoPatternKind::checker);
    EXPECT_EQ(s.materials[2].color, (Vec3d{1, 1, 1}));  // white by default
    EXPECT_EQ(s.materials[3].pattern.kind, AlbedoPatternKind::uniform);
    EXPECT_EQ(&s.materials[1], s.find_material("ball"));
}

TEST(SceneMaterial, RejectsBadMaterialKeys) {
    for (const char* bad : {
             "{name: a, colour: [1, 1, 1]}",                   // unknown key
             "{name: a, color: [1, 2, 0]}",                    // channel out of range
             "{name: a, color: 0.5}",                          // not three numbers
             "{name: a, pattern: {kind: sectors}}",            // unknown kind
             "{name: a, pattern: {kind: stripes, count: 1}}",  // too few segments
             "{name: a, pattern: {kind: checker, size_m: 0}}",
             "{name: a, pattern: {kind: checker, reflectance: 1.5}}",
             "{name: a, pattern: {kind: checker, axis: [1, 0, 0]}}",
             "{name: a, library: grass, reflectance: 0.5}",
         }) {
        const std::string yaml =
            std::string("materials: [") + bad + "]\nparts: [{sphere: {}, material: a}]\n";
        EXPECT_THROW(static_cast<void>(parse_scene_spec(yaml, "bad.yaml")), ConfigError) << bad;
    }
}

TEST(SceneMaterial, EachPartLaysItsPatternOnItsOwnSurface) {
    const Scene scene = build_scene(parse_scene_spec(R"(
materials:
  - {name: m, pattern: {kind: stripes}}
parts:
  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 10}
    material: m
  - sphere: {center_m: [0, 0, 0], radius_m: 1, exact: true}
    array: {count: [3, 1, 1], step_m: [10, 0, 0]}
    transform: {rotate_deg: [0, 0, 30]}
    material: m
  - sphere: {center_m: [0, 0, 5], radius_m: 2, subdivisions: 1}
    material: m
  - sphere: {center_m: [0, 0, 0], radius_m: 1, subdivisions: 1}
    array: {count: [2, 1, 1], step_m: [10, 0, 0]}
  - sphere: {center_m: [0, 0, 0], radius_m: 1, subdivisions: 1}
    transform: {scale: [1, 2, 1]}
)",
                                                     "mem.yaml"));
    ASSERT_EQ(scene.parts.size(), 5u);
    const ScenePart& plane = scene.parts[0];
    const PatternFrame pf = scene.pattern_frame(plane, plane.first_face);
    EXPECT_EQ(pf.surface, PatternSurface::plane);
    EXPECT_EQ(pf.u_axis, (Vec3d{0, -1, 0}));  // make_square's u for normal +z
    EXPECT_EQ(pf.w_axis, (Vec3d{1, 0, 0}));
    // The exact spheres: one frame per copy, in face order, with the part's attitude.
    const ScenePart& balls = scene.parts[1];
    ASSERT_EQ(balls.face_count, 3u);
    for (std::uint32_t k = 0; k < 3; ++k) {
        const PatternFrame f = scene.pattern_frame(balls, balls.first_face + k);
        EXPECT_EQ(f.surface, PatternSurface::sphere);
        EXPECT_NEAR(f.origin_m.x, 10.0 * k, 1e-12);
        EXPECT_EQ(f.radius_m, 1.0);
        EXPECT_NEAR(std::fabs(f.attitude.rotate({1, 0, 0}).y), 0.5, 1e-12);  // turned 30 deg
    }
    // A single icosphere: its analytic sphere, whichever triangle is hit.
    const ScenePart& ico = scene.parts[2];
    const PatternFrame f = scene.pattern_frame(ico, ico.first_face + ico.face_count - 1);
    EXPECT_EQ(f.surface, PatternSurface::sphere);
    EXPECT_EQ(f.origin_m, (Vec3d{0, 0, 5}));
    EXPECT_EQ(f.radius_m, 2.0);
    // Arrayed or stretched icospheres are solids (as in `render`: they have no analytic copy).
    EXPECT_EQ(scene.pattern_frame(scene.parts[3], scene.parts[3].first_face).surface,
              PatternSurface::solid);
    EXPECT_EQ(scene.pattern_frame(scene.parts[4], scene.parts[4].first_face).surface,
              PatternSurface::solid);
}

}  // namespace
}  // namespace beamtrace
