#include "beamtrace/scene/gltf_loader.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

[[nodiscard]] std::string base64(const std::string& bytes) {
    constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t chunk = 0;
        const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
        for (std::size_t k = 0; k < 3; ++k) {
            chunk = (chunk << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
        }
        for (std::size_t k = 0; k < 4; ++k) {
            out.push_back(k <= n ? kAlphabet[(chunk >> (18 - 6 * k)) & 63u] : '=');
        }
    }
    return out;
}

[[nodiscard]] std::string data_uri(const std::string& bytes) {
    return "data:application/octet-stream;base64," + base64(bytes);
}

void append_floats(std::string& out, std::initializer_list<float> values) {
    for (float v : values) {
        test::append_bytes(out, v);
    }
}

/// A GLB container holding `json` and, if not empty, a BIN chunk.
[[nodiscard]] std::string make_glb(std::string json, std::string bin) {
    while (json.size() % 4 != 0) {
        json.push_back(' ');
    }
    while (bin.size() % 4 != 0) {
        bin.push_back('\0');
    }
    std::string out = "glTF";
    test::append_bytes(out, std::uint32_t{2});
    const std::size_t total = 12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin.size());
    test::append_bytes(out, static_cast<std::uint32_t>(total));
    test::append_bytes(out, static_cast<std::uint32_t>(json.size()));
    test::append_bytes(out, std::uint32_t{0x4E4F534A});
    out += json;
    if (!bin.empty()) {
        test::append_bytes(out, static_cast<std::uint32_t>(bin.size()));
        test::append_bytes(out, std::uint32_t{0x004E4942});
        out += bin;
    }
    return out;
}

/// One triangle: three float positions (36 bytes) then u16 indices, in buffer 0.
struct OneTriangle {
    std::vector<std::uint16_t> indices{0, 1, 2};
    std::string uri;  ///< empty: a data URI with the bytes; "-": no uri (GLB chunk)
    int byte_length = -1;
    int position_count = 3;
    int positions_view_length = 36;
    std::string version = "2.0";
    int mode = 4;

    [[nodiscard]] std::string bytes() const {
        std::string b;
        append_floats(b, {0, 0, 0, 1, 0, 0, 0, 1, 0});
        for (auto i : indices) {
            test::append_bytes(b, i);
        }
        return b;
    }
    [[nodiscard]] std::string json() const {
        const std::string b = bytes();
        std::string buffer =
            R"({"byteLength": )" +
            std::to_string(byte_length < 0 ? static_cast<int>(b.size()) : byte_length);
        if (uri != "-") {
            buffer += R"(, "uri": ")" + (uri.empty() ? data_uri(b) : uri) + "\"";
        }
        buffer += "}";
        return R"({"asset": {"version": ")" + version + R"("}, "scene": 0,
            "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": )" +
               std::to_string(mode) + R"(}]}],
            "accessors": [
              {"bufferView": 0, "componentType": 5126, "count": )" +
               std::to_string(position_count) + R"(, "type": "VEC3"},
              {"bufferView": 1, "componentType": 5123, "count": )" +
               std::to_string(indices.size()) + R"(, "type": "SCALAR"}],
            "bufferViews": [
              {"buffer": 0, "byteOffset": 0, "byteLength": )" +
               std::to_string(positions_view_length) + R"(},
              {"buffer": 0, "byteOffset": 36, "byteLength": )" +
               std::to_string(2 * indices.size()) + R"(}],
            "buffers": [)" +
               buffer + "]}";
    }
};

class GltfLoaderTest : public test::TempDirTest {
  protected:
    /// Writes `t` as a .gltf and expects InputError naming the file with `fragment`.
    void expect_error(const OneTriangle& t, const std::string& fragment) const {
        test::expect_input_error(load_gltf, write("broken.gltf", t.json()), fragment);
    }
};

void expect_vec_near(const Vec3f& a, const Vec3f& b) {
    EXPECT_NEAR(a.x, b.x, 1e-5) << "y " << a.y << " z " << a.z;
    EXPECT_NEAR(a.y, b.y, 1e-5) << "x " << a.x << " z " << a.z;
    EXPECT_NEAR(a.z, b.z, 1e-5) << "x " << a.x << " y " << a.y;
}

[[nodiscard]] Vec3f face_normal(const TriangleMesh& m, std::size_t f) {
    const Vec3f a = m.vertices[m.faces[f][0]], b = m.vertices[m.faces[f][1]],
                c = m.vertices[m.faces[f][2]];
    return cross(b - a, c - a);
}

// ---- real files --------------------------------------------------------------------------

TEST(GltfLoader, BoxesHaveTwelveTrianglesAndTheSameGeometry) {
    const auto glb = test::shared_mesh("gltf/BoxTextured.glb");
    const auto gltf = test::shared_mesh("gltf/BoxTextured-glTF/BoxTextured.gltf");
    BEAMTRACE_REQUIRE_FILE(glb);
    BEAMTRACE_REQUIRE_FILE(gltf);
    const TriangleMesh a = load_gltf(glb);
    const TriangleMesh b = load_mesh(gltf);
    EXPECT_EQ(a.triangle_count(), 12u);
    EXPECT_EQ(a.vertices.size(), 24u);
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(a.vertices, b.vertices);
    const Aabb box = a.bounds();
    EXPECT_EQ(box.lo, Vec3f(-0.5f, -0.5f, -0.5f));
    EXPECT_EQ(box.hi, Vec3f(0.5f, 0.5f, 0.5f));
}

TEST(GltfLoader, BalloonAppliesNodeTransformsLikeAssimp) {
    const auto path = test::shared_mesh("vehicle/balloon/scene.gltf");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh m = load_gltf(path);
    EXPECT_EQ(m.triangle_count(), 35698u);
    EXPECT_EQ(m.vertices.size(), 25027u);
    // `assimp info scene.gltf -ptv` (assimp 5.2.5, vertices pre-transformed by the node tree).
    // Without the root's Z-up to Y-up matrix the box would be about (-0.14 -0.29 -0.36) to
    // (0.44 0.40 0.21).
    const Aabb box = m.bounds();
    expect_vec_near(box.lo, {-0.141432f, 0.213395f, -0.285986f});
    expect_vec_near(box.hi, {0.438397f, 0.908105f, 0.291778f});
}

TEST(GltfLoader, EngineInstancesEveryNodeMesh) {
    const auto path = test::shared_mesh("gltf/2CylinderEngine.glb");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh m = load_mesh(path);
    // SOURCES.md's 75730 counts each mesh once; several meshes are used by more than one node,
    // and the scene has 121496 triangles on 84657 vertices, as `assimp info -ptv` reports.
    EXPECT_EQ(m.triangle_count(), 121496u);
    EXPECT_EQ(m.vertices.size(), 84657u);
    const Aabb box = m.bounds();
    EXPECT_NEAR(box.lo.x, -371.692230f, 1e-3);
    EXPECT_NEAR(box.lo.y, -180.971558f, 1e-3);
    EXPECT_NEAR(box.lo.z, -140.0f, 1e-3);
    EXPECT_NEAR(box.hi.x, 371.692169f, 1e-3);
    EXPECT_NEAR(box.hi.y, 92.041565f, 1e-3);
    EXPECT_NEAR(box.hi.z, 128.0f, 1e-3);
}

TEST(GltfLoader, PrimitiveModesTriangulateOrSkip) {
    // Mesh_PrimitiveMode/README.md: 00-03 and 07-10 are points or lines; 04/11 strips, 05/12
    // fans, 06/13/14/15 triangles (13 u32, 14 u8, 15 u16 indices), each a unit square in z = 0.
    for (int i = 0; i < 16; ++i) {
        const std::string name =
            std::string("Mesh_PrimitiveMode_") + (i < 10 ? "0" : "") + std::to_string(i) + ".gltf";
        const auto path = test::shared_mesh("gltf/Mesh_PrimitiveMode/" + name);
        BEAMTRACE_REQUIRE_FILE(path);
        const bool triangles = (i >= 4 && i <= 6) || i >= 11;
        if (!triangles) {
            test::expect_input_error(load_gltf, path, "no triangles");
            continue;
        }
        const TriangleMesh m = load_gltf(path);
        ASSERT_EQ(m.triangle_count(), 2u) << name;
        float area = 0.0f;
        for (std::size_t f = 0; f < 2; ++f) {
            const Vec3f n = face_normal(m, f);
            EXPECT_GT(n.z, 0.0f) << name << " face " << f;  // every square faces +z
            area += 0.5f * n.z;
        }
        EXPECT_NEAR(area, 1.0f, 1e-6) << name;
    }
}

TEST(GltfLoader, IndexOutOfRangeFilesAreRejected) {
    for (const char* name : {"IndexOutOfRange", "AllIndicesOutOfRange"}) {
        const auto path = test::shared_mesh(std::string("gltf/IndexOutOfRange/") + name + ".gltf");
        BEAMTRACE_REQUIRE_FILE(path);
        test::expect_input_error(load_gltf, path, "accessors[0]: index ");
        test::expect_input_error(load_gltf, path, "out of range (24 vertices)");
    }
}

// ---- hand-written files ------------------------------------------------------------------

/// Node 0 (translation) -> node 1 (TRS, mesh 0); node 2 (matrix, mesh 0); node 3 (mesh 0) is
/// in no scene. Positions are interleaved (stride 16) behind 4 junk bytes; the u16 indices
/// start 2 bytes into their view.
[[nodiscard]] std::string transformed_scene(bool with_scene) {
    std::string b;
    append_floats(b, {-99.0f});
    append_floats(b, {1, 0, 0, -7, 0, 1, 0, -7, 0, 0, 1, -7});
    for (std::uint16_t i : std::initializer_list<std::uint16_t>{999, 0, 1, 2}) {
        test::append_bytes(b, i);
    }
    const std::string scene = with_scene ? R"("scene": 0, "scenes": [{"nodes": [0, 2]}],)" : "";
    return R"({"asset": {"version": "2.0"}, )" + scene + R"(
      "nodes": [
        {"translation": [10, 0, 0], "children": [1]},
        {"translation": [1, 2, 3], "rotation": [0, 0, 0.7071067811865476, 0.7071067811865476],
         "scale": [2, 2, 2], "mesh": 0},
        {"matrix": [3, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, -5, 1], "mesh": 0},
        {"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
        {"bufferView": 1, "byteOffset": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}],
      "bufferViews": [
        {"buffer": 0, "byteOffset": 4, "byteLength": 48, "byteStride": 16},
        {"buffer": 0, "byteOffset": 52, "byteLength": 8}],
      "buffers": [{"byteLength": 60, "uri": ")" +
           data_uri(b) + R"("}]})";
}

TEST_F(GltfLoaderTest, DataUriAndNodeTransformsGiveExactVertices) {
    const TriangleMesh m = load_gltf(write("trs.gltf", transformed_scene(true)));
    ASSERT_EQ(m.triangle_count(), 2u);  // node 3 is in no scene
    ASSERT_EQ(m.vertices.size(), 6u);
    // Node 1: p -> (1, 2, 3) + Rz(90 deg) (2 p), then node 0 adds (10, 0, 0).
    const std::vector<Vec3f> expected{{11, 4, 3}, {9, 2, 3},  {11, 2, 5},
                                      {3, 0, -5}, {0, 1, -5}, {0, 0, -4}};
    for (std::size_t f = 0; f < 2; ++f) {
        for (std::size_t c = 0; c < 3; ++c) {
            expect_vec_near(m.vertices[m.faces[f][c]], expected[3 * f + c]);
        }
    }
}

TEST_F(GltfLoaderTest, WithoutASceneEveryRootNodeIsWalkedInOrder) {
    const TriangleMesh m = load_gltf(write("roots.gltf", transformed_scene(false)));
    ASSERT_EQ(m.triangle_count(), 3u);  // roots 0 (-> 1), 2 and 3
    expect_vec_near(m.vertices[m.faces[0][0]], {11, 4, 3});
    expect_vec_near(m.vertices[m.faces[1][0]], {3, 0, -5});
    expect_vec_near(m.vertices[m.faces[2][0]], {1, 0, 0});
}

TEST_F(GltfLoaderTest, StripAndFanWindingFollowsTheSpecification) {
    std::string b;
    append_floats(b, {0, 1, 0, 0, 0, 0, 1, 1, 0, 1, 0, 0, 2, 1, 0});  // strip, 5 vertices
    append_floats(b, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0});           // fan, 4 vertices
    const std::string json = R"({"asset": {"version": "2.0"}, "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 5},
                                 {"attributes": {"POSITION": 1}, "mode": 6},
                                 {"attributes": {"POSITION": 1}, "mode": 3}]}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3"},
        {"bufferView": 0, "byteOffset": 60, "componentType": 5126, "count": 4, "type": "VEC3"}],
      "bufferViews": [{"buffer": 0, "byteLength": 108}],
      "buffers": [{"byteLength": 108, "uri": ")" +
                             data_uri(b) + R"("}]})";
    const TriangleMesh m = load_gltf(write("strip.gltf", json));
    const std::vector<Face> expected{{0, 1, 2}, {1, 3, 2}, {2, 3, 4}, {6, 7, 5}, {7, 8, 5}};
    EXPECT_EQ(m.faces, expected);
    for (std::size_t f = 0; f < m.triangle_count(); ++f) {
        EXPECT_GT(face_normal(m, f).z, 0.0f) << f;
    }
}

TEST_F(GltfLoaderTest, SparseAccessorAndNormalizedPositions) {
    std::string b;
    for (std::uint8_t i :
         std::initializer_list<std::uint8_t>{0, 2, 0, 0}) {  // sparse indices (u8) + padding
        test::append_bytes(b, i);
    }
    append_floats(b, {5, 5, 5, 7, 8, 9});  // sparse values for vertices 0 and 2
    for (std::uint16_t v :
         std::initializer_list<std::uint16_t>{0, 0, 0, 0, 65535, 0, 0, 0, 0, 65535, 0, 0}) {
        test::append_bytes(b, v);  // normalized u16 positions, stride 8
    }
    const std::string json = R"({"asset": {"version": "2.0"}, "nodes": [{"mesh": 0}, {"mesh": 1}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]},
                 {"primitives": [{"attributes": {"POSITION": 1}, "mode": 6}]}],
      "accessors": [
        {"componentType": 5126, "count": 3, "type": "VEC3",
         "sparse": {"count": 2, "indices": {"bufferView": 0, "componentType": 5121},
                    "values": {"bufferView": 1}}},
        {"bufferView": 2, "componentType": 5123, "normalized": true, "count": 3, "type": "VEC3"}],
      "bufferViews": [{"buffer": 0, "byteLength": 2},
                      {"buffer": 0, "byteOffset": 4, "byteLength": 24},
                      {"buffer": 0, "byteOffset": 28, "byteLength": 24, "byteStride": 8}],
      "buffers": [{"byteLength": 52, "uri": ")" +
                             data_uri(b) + R"("}]})";
    const TriangleMesh m = load_gltf(write("sparse.gltf", json));
    ASSERT_EQ(m.triangle_count(), 2u);
    expect_vec_near(m.vertices[0], {5, 5, 5});
    expect_vec_near(m.vertices[1], {0, 0, 0});
    expect_vec_near(m.vertices[2], {7, 8, 9});
    ASSERT_EQ(m.vertices.size(), 6u);
    expect_vec_near(m.vertices[3], {0, 0, 0});
    expect_vec_near(m.vertices[4], {1, 0, 0});
    expect_vec_near(m.vertices[5], {0, 1, 0});
}

TEST_F(GltfLoaderTest, GlbWithBinChunkMatchesTheGltf) {
    OneTriangle t;
    const TriangleMesh a = load_gltf(write("tri.gltf", t.json()));
    t.uri = "-";
    const std::string glb = make_glb(t.json(), t.bytes());
    const TriangleMesh b = load_gltf(write("tri.glb", glb));
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(load_mesh(write("TRI.GLB", glb)).vertices, a.vertices);
}

TEST_F(GltfLoaderTest, ExternalBufferWithPercentEscapes) {
    OneTriangle t;
    static_cast<void>(write("my buffer.bin", t.bytes()));
    t.uri = "my%20buffer.bin";
    EXPECT_EQ(load_gltf(write("ext.gltf", t.json())).triangle_count(), 1u);
}

// ---- broken files ------------------------------------------------------------------------

TEST_F(GltfLoaderTest, IndexOutOfRangeNamesTheAccessor) {
    OneTriangle t;
    t.indices = {0, 1, 30};
    expect_error(t, "broken.gltf: accessors[1]: index 30 out of range (3 vertices)");
}

TEST_F(GltfLoaderTest, MissingBufferFile) {
    OneTriangle t;
    t.uri = "missing.bin";
    expect_error(t, "buffers[0].uri: cannot read buffer file 'missing.bin'");
}

TEST_F(GltfLoaderTest, AccessorRunningPastItsBufferView) {
    OneTriangle t;
    t.position_count = 4;
    expect_error(t, "accessors[0]: byteOffset 0 + 4 elements of 12 bytes");
}

TEST_F(GltfLoaderTest, BufferViewRunningPastItsBuffer) {
    OneTriangle t;
    t.positions_view_length = 100;
    expect_error(t,
                 "bufferViews[0]: byteOffset 0 + byteLength 100 runs past the end of buffers[0]");
}

TEST_F(GltfLoaderTest, BufferShorterThanItsByteLength) {
    OneTriangle t;
    t.byte_length = 100;
    expect_error(t, "buffers[0]: byteLength 100 but the data has only 42 bytes");
}

TEST_F(GltfLoaderTest, WrongVersionAndMalformedJson) {
    OneTriangle t;
    t.version = "1.0";
    expect_error(t, "asset.version: '1.0'");
    test::expect_input_error(load_gltf, write("bad.gltf", R"({"asset": {"version": "2.0"}, )"),
                             "malformed JSON");
    test::expect_input_error(load_gltf, write("array.gltf", "[1, 2]"), "not an object");
}

TEST_F(GltfLoaderTest, NoTrianglesAtAll) {
    OneTriangle t;
    t.mode = 1;  // LINES
    t.indices = {0, 1};
    expect_error(t, "no triangles");
    t.mode = 9;
    expect_error(t, "meshes[0].primitives[0].mode: 9 is not a glTF primitive mode");
}

TEST_F(GltfLoaderTest, UnsupportedRequiredExtensionAndNodeCycle) {
    OneTriangle t;
    std::string json = t.json();
    json.insert(1, R"("extensionsRequired": ["KHR_draco_mesh_compression"], )");
    test::expect_input_error(load_gltf, write("draco.gltf", json), "KHR_draco_mesh_compression");
    json = t.json();
    const std::string nodes = R"("nodes": [{"mesh": 0}])";
    json.replace(json.find(nodes), nodes.size(), R"("nodes": [{"mesh": 0, "children": [0]}])");
    test::expect_input_error(load_gltf, write("cycle.gltf", json), "nodes[0]: is reached twice");
}

TEST_F(GltfLoaderTest, BrokenGlbContainers) {
    OneTriangle t;
    t.uri = "-";
    const std::string glb = make_glb(t.json(), t.bytes());
    std::string bad = glb;
    bad[3] = 'X';
    test::expect_input_error(load_gltf, write("magic.glb", bad), "GLB header: magic");
    bad = glb;
    bad[4] = 1;
    test::expect_input_error(load_gltf, write("version.glb", bad), "GLB header: version 1");
    test::expect_input_error(load_gltf, write("short.glb", glb.substr(0, glb.size() - 4)),
                             "GLB header: length");
    bad = glb;
    bad[16] = 'X';
    test::expect_input_error(load_gltf, write("chunk.glb", bad), "GLB chunk 0");
    t.uri = "";  // a GLB without a BIN chunk may use data URIs
    EXPECT_EQ(load_gltf(write("nobin.glb", make_glb(t.json(), ""))).triangle_count(), 1u);
    t.uri = "-";
    test::expect_input_error(load_gltf, write("nobin2.glb", make_glb(t.json(), "")),
                             "buffers[0]: has no uri");
}

TEST_F(GltfLoaderTest, TruncatedAndCorruptedFilesThrowOnlyInputError) {
    OneTriangle t;
    t.uri = "-";
    const std::string glb = make_glb(t.json(), t.bytes());
    const fs::path path = dir_ / "fuzz.glb";
    test::load_every_truncation(glb, [&](const std::string& bytes) {
        static_cast<void>(load_gltf(test::write_file(path, bytes)));
    });
    std::mt19937 rng(7);
    test::load_random_byte_flips(glb, rng, 300, [&](const std::string& bytes) {
        static_cast<void>(load_gltf(test::write_file(path, bytes)));
    });
    const fs::path text_path = dir_ / "fuzz.gltf";
    test::load_random_byte_flips(transformed_scene(true), rng, 300, [&](const std::string& bytes) {
        static_cast<void>(load_gltf(test::write_file(text_path, bytes)));
    });
    const auto box = test::shared_mesh("gltf/BoxTextured.glb");
    BEAMTRACE_REQUIRE_FILE(box);
    test::load_random_byte_flips(test::read_file(box), rng, 300, [&](const std::string& bytes) {
        static_cast<void>(load_gltf(test::write_file(path, bytes)));
    });
}

}  // namespace
}  // namespace beamtrace
