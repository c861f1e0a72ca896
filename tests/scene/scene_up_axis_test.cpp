// `up_axis: y` stands a y-up mesh upright: its +y becomes +z (a quarter turn about +x), before
// scale, rotation and translation; flat and instanced copies alike.
#include <gtest/gtest.h>

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(SceneUpAxis, AYUpMeshStandsUprightFlatOrInstanced) {
    const auto bunny = test::shared_data("meshes/small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(bunny);
    const TriangleMesh raw = load_mesh(bunny);
    Aabb raw_box;
    for (const auto& v : raw.vertices) {
        raw_box.extend(v);
    }
    test::TempDir dir;
    for (const char* array : {"", "    array: {count: [2, 1, 1], step_m: [100, 0, 0]}\n"}) {
        SCOPED_TRACE(array);
        const std::string yaml = "parts:\n  - mesh: " + bunny.string() +
                                 "\n    up_axis: y\n    transform: {scale: 10, translate_m: [0, "
                                 "0, 5]}\n" +
                                 array;
        const Scene scene = build_scene(parse_scene_spec(yaml, dir / "s.yaml"));
        const Aabb box = scene.geometry.instance_bounds(0);
        // x stays; the mesh's y (up) is the scene's z; its z is the scene's -y.
        EXPECT_NEAR(box.lo.x, 10 * raw_box.lo.x, 1e-4);
        EXPECT_NEAR(box.lo.z, 10 * raw_box.lo.y + 5, 1e-4);
        EXPECT_NEAR(box.hi.z, 10 * raw_box.hi.y + 5, 1e-4);
        EXPECT_NEAR(box.lo.y, -10 * raw_box.hi.z, 1e-4);
        EXPECT_NEAR(box.hi.y, -10 * raw_box.lo.z, 1e-4);
    }
}

TEST(SceneUpAxis, OnlyMeshesAndOnlyYOrZ) {
    const std::string sphere =
        "parts:\n  - sphere: {center_m: [0, 0, 0], radius_m: 1}\n    up_axis: y\n";
    EXPECT_THROW((void)parse_scene_spec(sphere, "s.yaml"), ConfigError);
    try {
        (void)parse_scene_spec(
            "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1]}\n    up_axis: x\n",
            "s.yaml");
        FAIL();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("parts[0].up_axis"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace beamtrace
