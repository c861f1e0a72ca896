// Library material names are checked where they are written, with file and line, whether or not
// a survey's physics will use them.
#include <gtest/gtest.h>

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/scene_spec.hpp"

namespace beamtrace {
namespace {

TEST(SceneLibraryNames, AnUnknownLibraryMaterialIsAnErrorWithFileAndLine) {
    const std::string yaml =
        "materials:\n  - {name: ok, library: grass}\n  - {name: typo, library: granit}\n"
        "parts:\n  - plane: {point_m: [0, 0, 0], normal: [0, 0, 1]}\n    material: ok\n";
    try {
        (void)parse_scene_spec(yaml, "scene.yaml");
        FAIL() << "accepted";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind("scene.yaml:3: materials[1].library: unknown library material "
                             "'granit' (known: asphalt, concrete, grass",
                             0),
                  0u)
            << what;
    }
    EXPECT_NO_THROW((void)parse_scene_spec(
        "materials:\n  - {name: ok, library: wood}\nparts:\n  - plane: {point_m: [0, 0, 0], "
        "normal: [0, 0, 1]}\n    material: ok\n",
        "scene.yaml"));
}

}  // namespace
}  // namespace beamtrace
