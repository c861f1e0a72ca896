#include <gtest/gtest.h>

#include <filesystem>
#include <random>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

class ObjLoaderTest : public test::TempDirTest {
  protected:
    /// Loading `bytes` must throw InputError naming the file, with `expected` in the message.
    void expect_error(const std::string& bytes, const std::string& expected) const {
        test::expect_input_error(load_obj, write("broken.obj", bytes), expected);
    }
};

TEST_F(ObjLoaderTest, QuadIsFanTriangulatedInFileOrder) {
    const auto mesh = load_obj(write("quad.obj",
                                     "v 0 0 0\n"
                                     "v 1 0 0\n"
                                     "v 1 1 0\n"
                                     "v 0 1 0.5\n"
                                     "f 1 2 3 4\n"));
    ASSERT_EQ(mesh.vertices.size(), 4u);
    EXPECT_EQ(mesh.vertices[3], Vec3f(0.0f, 1.0f, 0.5f));
    ASSERT_EQ(mesh.triangle_count(), 2u);
    EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));
    EXPECT_EQ(mesh.faces[1], (Face{0, 2, 3}));
}

TEST_F(ObjLoaderTest, PentagonThenTriangleKeepFaceIds) {
    const auto mesh = load_obj(write("penta.obj",
                                     "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n"
                                     "f 1 2 3 4 5\n"
                                     "f 5 4 3\n"));
    ASSERT_EQ(mesh.triangle_count(), 4u);
    EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));
    EXPECT_EQ(mesh.faces[1], (Face{0, 2, 3}));
    EXPECT_EQ(mesh.faces[2], (Face{0, 3, 4}));
    EXPECT_EQ(mesh.faces[3], (Face{4, 3, 2}));
}

TEST_F(ObjLoaderTest, AllIndexFormsAndNegativeIndices) {
    const auto mesh = load_obj(write("forms.obj",
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                     "vt 0 0\nvt 1 0\nvt 0 1\n"
                                     "vn 0 0 1\nvn 1 0 0\n"
                                     "f 1 2 3\n"
                                     "f 1/1 2/2 4/3\n"
                                     "f 1//1 3//2 4//2\n"
                                     "f 2/2/1 3/3/1 4/1/2\n"
                                     "f -4 -3 -1\n"
                                     "f -1/1/1 -2//1 -3/2\n"));
    ASSERT_EQ(mesh.triangle_count(), 6u);
    EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));
    EXPECT_EQ(mesh.faces[1], (Face{0, 1, 3}));
    EXPECT_EQ(mesh.faces[2], (Face{0, 2, 3}));
    EXPECT_EQ(mesh.faces[3], (Face{1, 2, 3}));
    EXPECT_EQ(mesh.faces[4], (Face{0, 1, 3}));
    EXPECT_EQ(mesh.faces[5], (Face{3, 2, 1}));
}

TEST_F(ObjLoaderTest, NegativeIndicesAreRelativeToVerticesReadSoFar) {
    const auto mesh = load_obj(write("relative.obj",
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                     "f -3 -2 -1\n"
                                     "v 5 5 5\nv 6 5 5\nv 5 6 5\n"
                                     "f -3 -2 -1\n"));
    ASSERT_EQ(mesh.triangle_count(), 2u);
    EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));
    EXPECT_EQ(mesh.faces[1], (Face{3, 4, 5}));
}

TEST_F(ObjLoaderTest, IgnoresCommentsOtherStatementsWAndColours) {
    const auto mesh = load_obj(write("noise.obj",
                                     "# a comment\r\n"
                                     "mtllib scene.mtl\r\n"
                                     "o object\r\n"
                                     "g group\r\n"
                                     "\r\n"
                                     "s off\r\n"
                                     "usemtl red\r\n"
                                     "v 1.5 -2e1 +3 1.0\r\n"
                                     "v\t0 0 0 0.1 0.2 0.3\r\n"
                                     "  v 1 1 1   # trailing comment\r\n"
                                     "vp 0.5 0.5\r\n"
                                     "l 1 2\r\n"
                                     "p 1\r\n"
                                     "curv2 1 2\r\n"
                                     "f 1 2 3 # comment after a face\r\n"
                                     "f 3 2 1"));  // no final line break
    ASSERT_EQ(mesh.vertices.size(), 3u);
    EXPECT_EQ(mesh.vertices[0], Vec3f(1.5f, -20.0f, 3.0f));
    EXPECT_EQ(mesh.vertices[1], Vec3f(0.0f, 0.0f, 0.0f));
    EXPECT_EQ(mesh.vertices[2], Vec3f(1.0f, 1.0f, 1.0f));
    ASSERT_EQ(mesh.triangle_count(), 2u);
    EXPECT_EQ(mesh.faces[1], (Face{2, 1, 0}));
}

TEST_F(ObjLoaderTest, BackslashContinuesALine) {
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 \\\n1 \\\n0\n"  // lines 1-6
        "f 1 2 \\\r\n 3 4\n"                            // lines 7-8
        "f 4 3 2\n";                                    // line 9
    const auto mesh = load_obj(write("continued.obj", text));
    ASSERT_EQ(mesh.vertices.size(), 4u);
    EXPECT_EQ(mesh.vertices[3], Vec3f(0.0f, 1.0f, 0.0f));
    ASSERT_EQ(mesh.triangle_count(), 3u);
    EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));
    EXPECT_EQ(mesh.faces[1], (Face{0, 2, 3}));
    EXPECT_EQ(mesh.faces[2], (Face{3, 2, 1}));
    // Line numbers stay right after continued lines.
    expect_error(text + "f 1 2\n", "broken.obj:10: face has 2 vertices");
}

TEST_F(ObjLoaderTest, DegenerateTrianglesAreKept) {
    const auto mesh = load_obj(write("degenerate.obj",
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                     "f 1 1 1\n"
                                     "f 1 2 3\n"
                                     "f 2 2 3\n"));
    ASSERT_EQ(mesh.triangle_count(), 3u);
    EXPECT_EQ(mesh.faces[0], (Face{0, 0, 0}));
    EXPECT_EQ(mesh.faces[1], (Face{0, 1, 2}));
    EXPECT_EQ(mesh.faces[2], (Face{1, 1, 2}));
}

TEST_F(ObjLoaderTest, MissingFileThrowsWithName) {
    test::expect_input_error(load_obj, dir_ / "does_not_exist.obj");
}

TEST_F(ObjLoaderTest, BrokenInputsThrowWithFileAndLine) {
    expect_error("v 0 0 0\nv 1 0 0\nv 0 x 0\nf 1 2 3\n", "broken.obj:3: malformed number 'x'");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n", "broken.obj:3: vertex needs 3");
    expect_error("v 0 0 0\nv 1 0\t0\nv 0 1 0\nf 1 2\n", "broken.obj:4: face has 2 vertices");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "broken.obj:4: face index 0");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "broken.obj:4: face index 4 is out");
    // A face may not refer to a vertex defined after it.
    expect_error("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n", "broken.obj:3: face index 3 is out");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "broken.obj:4: face index -4 is out");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3a\n", "broken.obj:4: malformed face index");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 /3\n", "broken.obj:4: malformed face index");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 1e999\nf 1 2 3\n", "broken.obj:3:");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n", "broken.obj:3:");
    expect_error("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no triangles");
    expect_error("", "no triangles");
}

TEST_F(ObjLoaderTest, EveryTruncationAndByteFlipThrowsInputErrorOrLoads) {
    const std::string bytes =
        "# pyramid\nv 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nv 1 1 3\n"
        "vt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3//1 4\nf -1 -2 -3\n";
    test::load_every_truncation(bytes, [&](const std::string& cut) {
        const auto mesh = load_obj(write("cut.obj", cut));
        EXPECT_GE(mesh.triangle_count(), 1u);
    });
    std::mt19937 rng(42);
    test::load_random_byte_flips(bytes, rng, 300, [&](const std::string& corrupt) {
        const auto mesh = load_obj(write("flip.obj", corrupt));
        EXPECT_NO_THROW(mesh.check_indices("flip.obj"));
    });
}

TEST_F(ObjLoaderTest, DirectoryIsNotAFile) {
    EXPECT_THROW((void)load_obj(dir_.path()), InputError);
}

TEST(ObjLoaderSharedData, RealFilesHaveTheExpectedTriangleCounts) {
    BEAMTRACE_REQUIRE_FILE(test::shared_mesh(""));
    struct Case {
        const char* file;
        std::size_t triangles;
        std::size_t vertices;
    };
    for (const Case& c :
         {Case{"small/stanford-bunny.obj", 69451, 35947}, Case{"small/spot.obj", 5856, 2930},
          Case{"terrain/dem_hd_sub_heightfield.obj", 46492, 23562},
          Case{"vehicle/legocar.obj", 10992, 5968},
          Case{"vegetation/white_birch.obj", 39239, 29757}}) {
        SCOPED_TRACE(c.file);
        const auto mesh = load_obj(test::shared_mesh(c.file));
        EXPECT_EQ(mesh.triangle_count(), c.triangles);
        EXPECT_EQ(mesh.vertices.size(), c.vertices);
        EXPECT_NO_THROW(mesh.check_indices(c.file));
    }
}

TEST(ObjLoaderSharedData, BunnyBoundsAreThoseOfTheStanfordBunny) {
    const fs::path path = test::shared_mesh("small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const auto mesh = load_obj(path);
    const Aabb box = mesh.bounds();
    // The zippered Stanford bunny is about 0.156 x 0.153 x 0.121 m.
    EXPECT_NEAR(box.extent().x, 0.156f, 0.002f);
    EXPECT_NEAR(box.extent().y, 0.153f, 0.002f);
    EXPECT_NEAR(box.extent().z, 0.121f, 0.002f);
}

TEST_F(ObjLoaderTest, LoadMeshDispatchesOnCaseInsensitiveExtension) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    EXPECT_EQ(load_mesh(write("upper.OBJ", tri)).triangle_count(), 1u);
    EXPECT_EQ(load_mesh(write("lower.obj", tri)).triangle_count(), 1u);
    try {
        (void)load_mesh(write("mesh.xyz", tri));
        FAIL() << "no exception";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("mesh.xyz"), std::string::npos) << what;
        EXPECT_NE(what.find("unknown mesh format"), std::string::npos) << what;
    }
    EXPECT_THROW((void)load_mesh(write("no_extension", tri)), InputError);
}

}  // namespace
}  // namespace beamtrace
