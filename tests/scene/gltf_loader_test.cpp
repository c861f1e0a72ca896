#include "beamtrace/scene/gltf_loader.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "corruption_support.hpp"
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

// ---- damaged files: refused, or loaded with only what the damage can reach changed ---------

/// Where one primitive's data sits in its buffer: VEC3 float positions `stride` bytes apart and
/// u16 indices, the primitive drawn by `instances` nodes (each instance appends its vertices and
/// faces to the mesh in turn).
struct PrimitiveLayout {
    std::size_t positions = 0, stride = 12, vertex_count = 3;
    std::size_t indices = 36, index_count = 3;
    std::size_t instances = 1;
};

/// What a damaged file may load as: only these vertices and faces changed, or, for damage to the
/// JSON, which may legitimately mean anything (a digit of a translation), any well-formed mesh.
struct MeshAllowance {
    bool anything = false;
    std::set<std::size_t> vertices, faces;
};

/// Allows what a change to byte `b` of the buffer reaches: one position (in every instance) or
/// one index's face; nothing for bytes no accessor reads.
void allow_buffer_byte(const PrimitiveLayout& l, std::size_t b, MeshAllowance& may) {
    if (b >= l.positions && (b - l.positions) % l.stride < 12 &&
        (b - l.positions) / l.stride < l.vertex_count) {
        for (std::size_t k = 0; k < l.instances; ++k) {
            may.vertices.insert((b - l.positions) / l.stride + k * l.vertex_count);
        }
    }
    if (b >= l.indices && b < l.indices + 2 * l.index_count) {
        for (std::size_t k = 0; k < l.instances; ++k) {
            may.faces.insert((b - l.indices) / 6 + k * (l.index_count / 3));
        }
    }
}

/// A flip at `offset` of a GLB: container headers and the JSON chunk's padding reach nothing,
/// the JSON anything, the BIN chunk what allow_buffer_byte says.
MeshAllowance glb_allowance(const std::string& glb, const PrimitiveLayout& l, std::size_t offset) {
    std::uint32_t json_length = 0;
    std::memcpy(&json_length, glb.data() + 12, 4);
    const std::size_t json_end = 20 + json_length;
    MeshAllowance may;
    if (offset >= 20 && offset < json_end) {
        may.anything = offset <= glb.rfind('}', json_end - 1);
    } else if (offset >= json_end + 8) {
        allow_buffer_byte(l, offset - json_end - 8, may);
    }
    return may;
}

/// A flip at `offset` of a .gltf whose only buffer is a base64 data URI: a character of the
/// payload reaches the 3 bytes of its 4-character group, any other byte anything.
MeshAllowance data_uri_allowance(const std::string& text, const PrimitiveLayout& l,
                                 std::size_t offset) {
    const std::size_t begin = text.find(";base64,") + 8;
    const std::size_t end = text.find('"', begin);
    MeshAllowance may;
    if (offset < begin || offset >= end) {
        may.anything = true;
        return may;
    }
    for (std::size_t b = (offset - begin) / 4 * 3, k = 0; k < 3; ++k) {
        allow_buffer_byte(l, b + k, may);
    }
    return may;
}

/// Fails the test unless `got` is well formed and differs from `want` only as `may` allows.
void expect_within(const TriangleMesh& got, const TriangleMesh& want, const MeshAllowance& may) {
    for (const Face& f : got.faces) {
        ASSERT_TRUE(f[0] < got.vertices.size() && f[1] < got.vertices.size() &&
                    f[2] < got.vertices.size())
            << "a face refers to a vertex that does not exist";
    }
    if (may.anything) {
        return;
    }
    ASSERT_EQ(got.vertices.size(), want.vertices.size());
    ASSERT_EQ(got.faces.size(), want.faces.size());
    for (std::size_t v = 0; v < got.vertices.size(); ++v) {
        EXPECT_TRUE(may.vertices.contains(v) || got.vertices[v] == want.vertices[v])
            << "vertex " << v << " changed";
    }
    for (std::size_t f = 0; f < got.faces.size(); ++f) {
        EXPECT_TRUE(may.faces.contains(f) || got.faces[f] == want.faces[f])
            << "face " << f << " changed";
    }
}

TEST_F(GltfLoaderTest, TruncatedFilesAreRefusedUnlessOnlyPaddingIsCut) {
    OneTriangle t;
    t.uri = "-";
    const std::string glb = make_glb(t.json(), t.bytes());
    const auto load = [&](const std::string& bytes) {
        return load_gltf(test::write_file(dir_ / "cut.glb", bytes));
    };
    const TriangleMesh want = load(glb);
    const std::size_t unpadded = glb.size() - (4 - t.bytes().size() % 4) % 4;
    // Only the BIN chunk's 2 bytes of padding are unused; even then the header's length is wrong.
    test::check_every_truncation(glb, load, [&](const TriangleMesh& got, std::size_t n) {
        ASSERT_GE(n, unpadded) << "a GLB cut before its padding loaded";
        expect_within(got, want, {});
    });
    // A .gltf cut anywhere is malformed JSON, whatever holds its buffer.
    const auto load_text = [&](const std::string& bytes) {
        return load_gltf(test::write_file(dir_ / "cut.gltf", bytes));
    };
    test::check_every_truncation(transformed_scene(true), load_text,
                                 [](const TriangleMesh&, std::size_t) {
                                     ADD_FAILURE() << "a truncated .gltf with a data URI loaded";
                                 });
    t.uri = "tri.bin";
    const std::string external = t.json();
    static_cast<void>(write("tri.bin", t.bytes()));
    test::check_every_truncation(external, load_text, [](const TriangleMesh&, std::size_t) {
        ADD_FAILURE() << "a truncated .gltf with an external buffer loaded";
    });
    // The external buffer itself, with 2 bytes past its byteLength that no one reads.
    const std::string bin = t.bytes() + std::string(2, '\0');
    const fs::path gltf_path = write("ext.gltf", external);
    test::check_every_truncation(
        bin,
        [&](const std::string& bytes) {
            static_cast<void>(write("tri.bin", bytes));
            return load_gltf(gltf_path);
        },
        [&](const TriangleMesh& got, std::size_t n) {
            ASSERT_GE(n, t.bytes().size()) << "a buffer shorter than its byteLength loaded";
            expect_within(got, want, {});
        });
}

TEST_F(GltfLoaderTest, ByteFlipsAreRefusedOrChangeOnlyWhatTheyHit) {
    const fs::path path = dir_ / "fuzz.glb";
    const auto load = [&](const std::string& bytes) {
        return load_gltf(test::write_file(path, bytes));
    };
    std::mt19937 rng(7);
    OneTriangle t;
    t.uri = "-";
    const std::string glb = make_glb(t.json(), t.bytes());
    const TriangleMesh tri = load(glb);
    test::check_random_byte_flips(glb, rng, 300, load,
                                  [&](const TriangleMesh& got, const test::ByteFlip& flip) {
                                      expect_within(got, tri, glb_allowance(glb, {}, flip.offset));
                                  });
    // Positions at 4 + 16 i, indices 2 bytes into their view at 52; two nodes draw the mesh.
    const std::string text = transformed_scene(true);
    const fs::path text_path = dir_ / "fuzz.gltf";
    const auto load_text = [&](const std::string& bytes) {
        return load_gltf(test::write_file(text_path, bytes));
    };
    const TriangleMesh scene = load_text(text);
    const PrimitiveLayout scene_layout{4, 16, 3, 54, 3, 2};
    test::check_random_byte_flips(
        text, rng, 300, load_text, [&](const TriangleMesh& got, const test::ByteFlip& flip) {
            expect_within(got, scene, data_uri_allowance(text, scene_layout, flip.offset));
        });
    // BoxTextured.glb's JSON: POSITION is accessor 2, 24 VEC3 at byte 288 of its buffer (stride
    // 12); the 36 u16 indices are at byte 768; normals, texture coordinates and the PNG around
    // them are read by no one.
    const auto box_path = test::shared_mesh("gltf/BoxTextured.glb");
    BEAMTRACE_REQUIRE_FILE(box_path);
    const std::string box_bytes = test::read_file(box_path);
    const TriangleMesh box = load(box_bytes);
    const PrimitiveLayout box_layout{288, 12, 24, 768, 36, 1};
    test::check_random_byte_flips(
        box_bytes, rng, 300, load, [&](const TriangleMesh& got, const test::ByteFlip& flip) {
            expect_within(got, box, glb_allowance(box_bytes, box_layout, flip.offset));
        });
}

}  // namespace
}  // namespace beamtrace
