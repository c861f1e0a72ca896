// Scene files that used to escape parse_scene_spec as yaml-cpp or filesystem exceptions, or
// inflate memory (issue 15, findings 1, 3, 5): each is a ConfigError naming the file, line, key.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr const char* kPlane = "plane: {point_m: [0, 0, -2], normal: [0, 0, 1], size_m: 40}";

/// The ConfigError message of parsing `yaml` as `source`; fails on any other outcome.
std::string config_error(const std::string& yaml, const std::filesystem::path& source) {
    try {
        (void)parse_scene_spec(yaml, source);
    } catch (const ConfigError& e) {
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not a ConfigError: " << e.what();
        return {};
    }
    ADD_FAILURE() << "accepted";
    return {};
}

TEST(SceneYamlHostile, ListsAndMapsAsKeysAreConfigErrors) {
    for (const std::string& yaml :
         {std::string("[a]: 1\nparts:\n  - ") + kPlane + "\n",
          std::string("parts:\n  - {[a]: 1, ") + kPlane + "}\n",
          std::string("parts:\n  - ") + kPlane + "\n    transform: {{x: 1}: 2}\n",
          std::string("materials:\n  - {name: m, [a, b]: 1}\nparts:\n  - ") + kPlane + "\n"}) {
        SCOPED_TRACE(yaml);
        const std::string msg = config_error(yaml, "s.yaml");
        EXPECT_EQ(msg.rfind("s.yaml:", 0), 0u) << msg;
        EXPECT_NE(msg.find("a key must be a name"), std::string::npos) << msg;
    }
}

TEST(SceneYamlHostile, NamesTheFileSystemRefusesAreConfigErrors) {
    test::TempDir dir;
    std::filesystem::create_symlink("loop", dir / "loop");
    const std::string long_name(300, 'm');
    const std::string msg_long =
        config_error("parts:\n  - mesh: " + long_name + ".obj\n", dir / "s.yaml");
    EXPECT_NE(msg_long.find("s.yaml:2: parts[0].mesh: cannot check the file '" +
                            std::string(80, 'm') + "...': File name too long"),
              std::string::npos)
        << msg_long;
    const std::string msg_loop = config_error("parts:\n  - raster: loop/dem.tif\n", dir / "s.yaml");
    EXPECT_NE(msg_loop.find("s.yaml:2: parts[0].raster: cannot check the file " +
                            (dir / "loop/dem.tif").string()),
              std::string::npos)
        << msg_loop;
}

TEST(SceneYamlHostile, CopyCountsAreLimitedBeforeAnythingIsAllocated) {
    const auto part = [](const std::string& count) {
        return std::string("  - ") + kPlane + "\n    array: {count: " + count + "}\n";
    };
    EXPECT_NE(config_error("parts:\n" + part("[10000, 10000, 1]"), "s.yaml")
                  .find("s.yaml:3: parts[0].array.count: 100000000 copies, more than the limit "
                        "of 1000000 copies of a part"),
              std::string::npos);
    EXPECT_NE(config_error("parts:\n" + part("[1000001, 1, 1]"), "s.yaml")
                  .find("parts[0].array.count: expected an integer in [1, 1000000]"),
              std::string::npos);
    // Each part within the limit, together over it.
    EXPECT_NE(config_error("parts:\n" + part("[1000, 1000, 1]") + part("[2, 1, 1]"), "s.yaml")
                  .find("s.yaml:2: parts: 1000002 copies of parts in all, more than the limit of "
                        "1000000 copies in a scene"),
              std::string::npos);
    // At the limit: accepted.
    const SceneSpec ok = parse_scene_spec("parts:\n" + part("[1000, 1000, 1]"), "s.yaml");
    EXPECT_EQ(ok.parts.at(0).array.copies(), 1000000u);
}

TEST(SceneYamlHostile, ManyProblemsAreListedUpToFifty) {
    std::string yaml = "parts:\n";
    for (int i = 0; i < 1000; ++i) {
        yaml += "  - {sphere: {radius_m: -1}}\n";
    }
    const std::string msg = config_error(yaml, "s.yaml");
    EXPECT_EQ(msg.rfind("1000 problem(s) in the scene file:", 0), 0u) << msg.substr(0, 200);
    EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 51) << msg;
    EXPECT_NE(msg.find("\n  ... and 950 more"), std::string::npos) << msg;
}

TEST(SceneYamlHostile, TextsOfTooManyNodesAreRefusedBeforeBuildingThem) {
    std::string yaml = "parts:\n  - {plane: {size_m: 1}}\nmaterials: [";
    for (int i = 0; i < 200000; ++i) {
        yaml += "1,";
    }
    yaml += "]\n";
    EXPECT_EQ(config_error(yaml, "s.yaml"),
              "s.yaml: more than 200000 YAML nodes (values, lists and maps), the limit for a "
              "config file");
    // Syntax errors are still reported with their line.
    EXPECT_EQ(config_error("parts:\n  - [\n", "s.yaml").rfind("s.yaml:", 0), 0u);
}

TEST(SceneYamlHostile, LongValuesAreQuotedClipped) {
    const std::string big(std::size_t{1} << 20, 'z');
    for (const std::string& yaml :
         {std::string("parts:\n  - ") + kPlane + "\n    material: " + big + "\n",
          std::string("parts:\n  - ") + kPlane + "\n    label: " + big + "\n",
          std::string("materials:\n  - {name: " + big + "}\n  - {name: " + big +
                      "}\nparts:\n  - ") +
              kPlane + "\n",
          std::string("parts:\n  - ") + kPlane + "\n    ? " + big + "\n    : 1\n"}) {
        const std::string msg = config_error(yaml, "s.yaml");
        EXPECT_LT(msg.size(), 400u) << msg.substr(0, 400);
        EXPECT_NE(msg.find(big.substr(0, 80) + "..."), std::string::npos) << msg.substr(0, 400);
    }
}

}  // namespace
}  // namespace beamtrace
