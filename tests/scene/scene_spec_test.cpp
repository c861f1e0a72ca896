#include "beamtrace/scene/scene_spec.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(SceneSpec, ParsesPartsMaterialsAndTransforms) {
    test::TempDir dir;
    test::write_file(dir / "box.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string yaml = R"(
origin_m: [500000, 5400000, 0]
materials:
  - {name: asphalt, reflectance: 0.1}
  - {name: paint, reflectance: 0.6, specular_weight: 0.3, specular_exponent: 40}
parts:
  - mesh: box.obj
    name: car
    transform: {translate_m: [10, 20, 0], rotate_deg: [0, 0, 90], scale: 2}
    material: paint
    label: 64
  - sphere: {center_m: [0, 0, 5], radius_m: 2.5, subdivisions: 2}
  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 50}
    material: asphalt
    label: 2
    part_id: 7
)";
    const SceneSpec s = parse_scene_spec(yaml, dir / "scene.yaml");
    EXPECT_EQ(s.origin_m, (Vec3d{500000, 5400000, 0}));
    ASSERT_EQ(s.materials.size(), 3u);  // "default" comes first
    EXPECT_EQ(s.materials[0].name, "default");
    EXPECT_DOUBLE_EQ(s.materials[2].specular_exponent, 40.0);
    ASSERT_EQ(s.parts.size(), 3u);
    const PartSpec& car = s.parts[0];
    EXPECT_EQ(car.kind, PartKind::mesh);
    EXPECT_EQ(car.name, "car");
    EXPECT_EQ(car.file, dir / "box.obj");
    EXPECT_EQ(car.label, 64);
    EXPECT_EQ(car.part_id, 1);
    EXPECT_EQ(car.material, "paint");
    EXPECT_NEAR(car.transform.rotate.yaw_rad, std::numbers::pi / 2, 1e-15);
    // Scale 2, then yaw 90 degrees (the report's convention turns +x to -y), then translate.
    const Vec3d p = car.transform.apply({1, 0, 0});
    EXPECT_NEAR(p.x, 10.0, 1e-12);
    EXPECT_NEAR(p.y, 18.0, 1e-12);
    EXPECT_EQ(s.parts[1].kind, PartKind::sphere);
    EXPECT_EQ(s.parts[1].name, "part-2");
    EXPECT_DOUBLE_EQ(s.parts[1].radius_m, 2.5);
    EXPECT_EQ(s.parts[2].kind, PartKind::plane);
    EXPECT_EQ(s.parts[2].part_id, 7);
    EXPECT_EQ(s.parts[2].label, 2);
}

TEST(SceneSpec, ReportsEveryProblemWithLineAndKey) {
    const std::string yaml = R"(parts:
  - mesh: missing.obj
    label: 300
  - sphere: {radius_m: -1}
    material: chrome
  - plane: {normal: [0, 0, 0]}
    transform: {scale: [1, 0, 1], spin: 3}
  - name: nothing
  - mesh: a.obj
    sphere: {radius_m: 1}
)";
    try {
        (void)parse_scene_spec(yaml, "scene.yaml");
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const char* needle :
             {"scene.yaml:2: parts[0].mesh: file not found", "scene.yaml:3: parts[0].label",
              "scene.yaml:4: parts[1].sphere.radius_m: must be positive",
              "scene.yaml:5: parts[1].material: unknown material 'chrome'",
              "scene.yaml:6: parts[2].plane.normal: must not be zero",
              "parts[2].transform.scale: scale factors must be positive",
              "parts[2].transform.spin: unknown key",
              "scene.yaml:8: parts[3]: needs exactly one of mesh, raster, sphere, plane",
              "scene.yaml:9: parts[4]: needs exactly one"}) {
            EXPECT_NE(msg.find(needle), std::string::npos) << needle << "\n" << msg;
        }
    }
}

TEST(SceneSpec, RejectsBrokenYamlAndWrongShapes) {
    EXPECT_THROW((void)parse_scene_spec("parts: [", "a.yaml"), ConfigError);
    EXPECT_THROW((void)parse_scene_spec("- 1\n- 2\n", "a.yaml"), ConfigError);
    EXPECT_THROW((void)parse_scene_spec("parts: []\n", "a.yaml"), ConfigError);
    EXPECT_THROW((void)parse_scene_spec("origin_m: [1, 2]\nparts:\n  - sphere: {}\n", "a.yaml"),
                 ConfigError);
    EXPECT_THROW((void)load_scene_spec("/nonexistent/scene.yaml"), InputError);
}

/// The message of the ConfigError that loading `yaml` (written as dir/scene.yaml) throws.
std::string scene_error(const test::TempDir& dir, const std::string& yaml) {
    const auto path = test::write_file(dir / "scene.yaml", yaml);
    try {
        (void)load_scene_spec(path);
    } catch (const ConfigError& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected a ConfigError for\n" << yaml;
    return {};
}

TEST(SceneSpec, SyntaxErrorsAndBadKeysNameTheExactLine) {
    test::TempDir dir;
    const std::string file = (dir / "scene.yaml").string();
    // Comments and blank lines count: the lines are those of the file as an editor shows them.
    const std::string head = R"(# a scene
materials:
  - {name: paint, reflectance: 0.6}

parts:
  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1], size_m: 10}
)";
    // Line 7: a flow sequence closed twice.
    const std::string flow =
        scene_error(dir, head + "  - sphere: {center_m: [0, 0, 1]], radius_m: 1}\n");
    EXPECT_EQ(flow.rfind(file + ":7: not valid YAML", 0), 0u) << flow;
    // Line 8: a key indented deeper than its map.
    const std::string mis = scene_error(dir, head + "  - mesh: a.obj\n      label: 2\n");
    EXPECT_EQ(mis.rfind(file + ":8: not valid YAML", 0), 0u) << mis;
    // Line 9: an unknown key in a part's block map, the only problem: the whole message.
    const std::string key = scene_error(
        dir, head +
                 "  - sphere: {center_m: [0, 0, 1], radius_m: 1}\n    label: 4\n    colour: "
                 "red\n");
    EXPECT_EQ(key.rfind(file + ":9: parts[1].colour: unknown key", 0), 0u) << key;
    // Line 11: a bad value after a multi-line flow map.
    const std::string value = scene_error(dir, head + R"(  - sphere:
      {center_m: [0, 0, 1],
       radius_m: 1}
    label: 4
    material: chrome
)");
    EXPECT_EQ(value.rfind(file + ":11: parts[1].material: unknown material 'chrome'", 0), 0u)
        << value;
}

}  // namespace
}  // namespace beamtrace
