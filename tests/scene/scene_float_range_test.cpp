// Scene parts whose numbers are finite doubles but not finite floats are refused when the scene
// is built, naming the scene file, the part and the setting (issue 15, finding 6).
#include <gtest/gtest.h>

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr const char* kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

class SceneFloatRange : public test::TempDirTest {
  protected:
    /// Building a scene of `parts` (after a ground plane) must fail naming the part and `what`.
    void expect_refused(const std::string& parts, const std::string& what) const {
        static_cast<void>(write("tri.obj", kTriangleObj));
        const auto path =
            write("scene.yaml", "parts:\n  - plane: {size_m: 10}\n    name: ground\n" + parts);
        const std::string message =
            test::expect_input_error([](const auto& p) { return load_scene_file(p); }, path, what);
        EXPECT_NE(message.find("is not finite in float"), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
};

TEST_F(SceneFloatRange, SphereCentreAndRadiusBeyondFloatAreRefused) {
    expect_refused("  - sphere: {center_m: [1e300, 0, 0], radius_m: 1}\n    name: far\n",
                   "part 'far': center_m (1e+300, 0, 0)");
    expect_refused("  - sphere: {radius_m: 1e39}\n    name: huge\n", "part 'huge': radius_m");
    // An exact sphere too.
    expect_refused(
        "  - sphere: {center_m: [0, 0, -1e40], radius_m: 1, exact: true}\n"
        "    name: exact\n",
        "part 'exact': center_m");
}

TEST_F(SceneFloatRange, TransformsThatOverflowFloatAreRefused) {
    expect_refused("  - mesh: tri.obj\n    name: big\n    transform: {scale: [1e40, 1, 1]}\n",
                   "part 'big': scale (1e+40, 1, 1)");
    expect_refused(
        "  - mesh: tri.obj\n    name: moved\n    transform: {translate_m: [0, 5e38, 0]}\n",
        "part 'moved': translate_m");
    // Each number fits, the vertex does not: 1 m scaled by 1e20 and then by 1e20 again.
    expect_refused(
        "  - mesh: tri.obj\n    name: scaled\n    transform: {scale: 1e20}\n"
        "  - sphere: {center_m: [0, 0, 0], radius_m: 1e20}\n    name: ball\n"
        "    transform: {scale: 1e20}\n",
        "part 'ball': vertex");
}

TEST_F(SceneFloatRange, ArraysAndSharedMeshesThatOverflowFloatAreRefused) {
    expect_refused(
        "  - mesh: tri.obj\n    name: row\n"
        "    array: {count: [10, 1, 1], step_m: [1e38, 0, 0]}\n",
        "part 'row': the last array copy's offset");
    expect_refused(
        "  - mesh: tri.obj\n    name: a\n"
        "  - mesh: tri.obj\n    name: b\n    transform: {translate_m: [3e38, 0, 0], scale: 1e38}\n",
        "part 'b': a copy's corner");
}

TEST_F(SceneFloatRange, LargeButFloatSizedPartsBuild) {
    static_cast<void>(write("tri.obj", kTriangleObj));
    const auto path = write("scene.yaml",
                            "parts:\n  - sphere: {center_m: [1e30, 0, 0], radius_m: 1e29}\n"
                            "  - mesh: tri.obj\n    transform: {scale: 1e30}\n"
                            "    array: {count: [2, 1, 1], step_m: [1e37, 0, 0]}\n");
    EXPECT_EQ(load_scene_file(path).parts.size(), 2u);
}

}  // namespace
}  // namespace beamtrace
