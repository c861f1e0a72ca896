// Scene files whose parts share a mesh or are arrayed: the mesh is stored once, face IDs are as
// if every copy were concatenated, and tracing gives what copying the triangles would give.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

// A unit cube centred on the origin (12 triangles, outward-facing).
constexpr const char* kCubeObj = R"(v -0.5 -0.5 -0.5
v 0.5 -0.5 -0.5
v 0.5 0.5 -0.5
v -0.5 0.5 -0.5
v -0.5 -0.5 0.5
v 0.5 -0.5 0.5
v 0.5 0.5 0.5
v -0.5 0.5 0.5
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
)";

TEST(SceneInstancing, SharedMeshAndArraysAreStoredOnce) {
    test::TempDir dir;
    test::write_file(dir / "cube.obj", kCubeObj);
    test::write_file(dir / "scene.yaml", R"(parts:
  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 100}
    label: 2
  - mesh: cube.obj
    name: tower
    transform: {translate_m: [0, 0, 5], rotate_deg: [0, 0, 30], scale: [2, 2, 10]}
    label: 6
  - mesh: cube.obj
    name: crates
    transform: {translate_m: [10, 10, 0.5]}
    array: {count: [3, 2, 1], step_m: [4, 5, 0]}
    label: 7
    part_id: 40
  - sphere: {center_m: [-20, 0, 3], radius_m: 2, subdivisions: 1}
)");
    const Scene s = load_scene_file(dir / "scene.yaml");
    ASSERT_EQ(s.parts.size(), 4u);
    // plane (2) + tower (12) + 6 crates (72) + sphere (80)
    EXPECT_EQ(s.triangle_count(), 2u + 12u + 72u + 80u);
    // The cube is stored once; plane and sphere are flat copies (two flat meshes: they are not
    // consecutive).
    EXPECT_EQ(s.geometry.stored_triangle_count(), 2u + 12u + 80u);
    EXPECT_EQ(s.geometry.meshes.size(), 3u);
    EXPECT_EQ(s.geometry.instances.size(), 1u + 1u + 6u + 1u);
    EXPECT_EQ(s.parts[1].first_face, 2u);
    EXPECT_EQ(s.parts[2].first_face, 14u);
    EXPECT_EQ(s.parts[2].face_count, 72u);
    EXPECT_EQ(s.parts[2].instance_count, 6u);
    EXPECT_EQ(s.parts[3].first_face, 86u);
    EXPECT_EQ(s.part_of_face(85), 2u);
    EXPECT_EQ(s.part_of_face(86), 3u);

    ThreadPool pool(2);
    const auto bvh = make_backend(BackendKind::bvh, s.geometry, pool);
    RayBatch rays;
    // Straight down onto crate (i=2, j=1) at (18, 15): its top at z = 1.
    rays.push_back({18.2, 15.1, 50.0}, {0, 0, -1});
    // Onto the tower: the scaled cube's top at z = 5 + 5 = 10.
    rays.push_back({0.1, 0.2, 50.0}, {0, 0, -1});
    // Horizontally into the tower's side: yawed 30 degrees, half-width 1 m.
    rays.push_back({-10.0, 0.0, 5.0}, {1, 0, 0});
    // Between the crates: the plane at z = 0.
    rays.push_back({12.0, 12.5, 50.0}, {0, 0, -1});
    const HitBatch h = bvh->intersect(rays, pool);
    ASSERT_TRUE(h.hit(0) && h.hit(1) && h.hit(2) && h.hit(3));
    EXPECT_NEAR(h.t[0], 49.0, 1e-5);
    EXPECT_EQ(s.part_of_face(h.face[0]), 2u);
    EXPECT_EQ((h.face[0] - 14u) / 12u, 5u);  // copy index x fastest: i + 3 j = 5
    EXPECT_NEAR(h.t[1], 40.0, 1e-5);
    EXPECT_EQ(s.part_of_face(h.face[1]), 1u);
    // The side face of a square of half-width 1 turned by 30 degrees is at distance 1 from the
    // axis, so a ray along +x meets it at x = -1 / cos(30 deg).
    EXPECT_NEAR(h.t[2], 10.0 - 1.0 / std::cos(std::numbers::pi / 6), 1e-5);
    EXPECT_NEAR(h.t[3], 50.0, 1e-5);
    EXPECT_EQ(s.part_of_face(h.face[3]), 0u);

    // Every backend and the flattened copy agree.
    const TriangleMesh flat = s.geometry.flatten();
    const auto brute_flat = make_backend(BackendKind::brute, flat, pool);
    const HitBatch hf = brute_flat->intersect(rays, pool);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        EXPECT_EQ(hf.face[i], h.face[i]) << i;
        EXPECT_NEAR(hf.t[i], h.t[i], 1e-5) << i;
    }
}

TEST(SceneInstancing, ArrayErrorsNameTheKey) {
    test::TempDir dir;
    test::write_file(dir / "cube.obj", kCubeObj);
    test::write_file(dir / "bad.yaml", R"(parts:
  - mesh: cube.obj
    array: {count: [0, 2], step_m: [1, 1, 1]}
  - mesh: cube.obj
    array: {count: [100000, 100000, 1000]}
  - mesh: cube.obj
    array: {step_m: [1, 1]}
)");
    try {
        (void)load_scene_file(dir / "bad.yaml");
        FAIL() << "expected a ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("bad.yaml:3: parts[0].array.count"), std::string::npos) << msg;
        EXPECT_NE(msg.find("bad.yaml:5: parts[1].array.count: 10000000000000 copies, more than "
                           "the limit of 1000000 copies"),
                  std::string::npos)
            << msg;
        EXPECT_NE(msg.find("parts[2].array.count: missing"), std::string::npos) << msg;
        EXPECT_NE(msg.find("parts[2].array.step_m"), std::string::npos) << msg;
    }
}

}  // namespace
}  // namespace beamtrace
