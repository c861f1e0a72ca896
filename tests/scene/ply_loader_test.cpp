#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

class PlyLoaderTest : public test::TempDirTest {
  protected:
    /// Loading `bytes` must throw InputError naming the file, with `expected` in the message.
    void expect_error(const std::string& bytes, const std::string& expected) const {
        test::expect_input_error(load_ply, write("broken.ply", bytes), expected);
    }
};

/// Appends values in a PLY scalar type, as text or binary in either byte order.
class PlyWriter {
  public:
    explicit PlyWriter(std::string format) : format_(std::move(format)) {}

    PlyWriter& value(const std::string& type, double v) {
        if (format_ == "ascii") {
            std::string text = std::to_string(v);
            if (type != "float" && type != "float32" && type != "double" && type != "float64") {
                text = std::to_string(static_cast<long long>(v));
            }
            data_ += text + " ";
        } else if (type == "char" || type == "int8") {
            put(static_cast<std::int8_t>(v));
        } else if (type == "uchar" || type == "uint8") {
            put(static_cast<std::uint8_t>(v));
        } else if (type == "short" || type == "int16") {
            put(static_cast<std::int16_t>(v));
        } else if (type == "ushort" || type == "uint16") {
            put(static_cast<std::uint16_t>(v));
        } else if (type == "int" || type == "int32") {
            put(static_cast<std::int32_t>(v));
        } else if (type == "uint" || type == "uint32") {
            put(static_cast<std::uint32_t>(v));
        } else if (type == "float" || type == "float32") {
            put(static_cast<float>(v));
        } else {
            put(v);
        }
        return *this;
    }
    PlyWriter& end_line() {
        if (format_ == "ascii") {
            data_ += "\n";
        }
        return *this;
    }
    [[nodiscard]] const std::string& data() const { return data_; }

  private:
    template <typename T>
    void put(T v) {
        test::append_bytes(data_, v,
                           format_ == "binary_big_endian" ? std::endian::big : std::endian::little);
    }

    std::string format_;
    std::string data_;
};

const std::vector<Vec3f> kPyramid{
    {0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1, 1, 3}};  // small integers: fit every type
const std::vector<Face> kPyramidFaces{{0, 1, 2}, {0, 2, 3}, {4, 3, 2}};

/// A pyramid (a quad and a triangle) with an extra element before the vertices, extra scalar and
/// list properties around x/y/z and around the index list.
[[nodiscard]] std::string make_ply(const std::string& format, const std::string& coord_type,
                                   const std::string& count_type, const std::string& index_type,
                                   const std::string& list_name = "vertex_indices") {
    std::string header = "ply\nformat " + format +
                         " 1.0\n"
                         "comment written by ply_loader_test\n"
                         "element edge 2\n"
                         "property list uchar int vertices\n"
                         "property uchar crease\n"
                         "element vertex 5\n"
                         "property float nx\n"
                         "property " +
                         coord_type +
                         " x\n"
                         "property list uchar short tags\n"
                         "property " +
                         coord_type + " y\nproperty uchar red\nproperty " + coord_type +
                         " z\n"
                         "property double confidence\n"
                         "element face 2\n"
                         "property int flags\n"
                         "property list " +
                         count_type + " " + index_type + " " + list_name +
                         "\n"
                         "property list uchar float texcoord\n"
                         "end_header\n";
    PlyWriter w(format);
    w.value("uchar", 2).value("int", 0).value("int", 1).value("uchar", 7).end_line();
    w.value("uchar", 0).value("uchar", 8).end_line();
    for (std::size_t i = 0; i < kPyramid.size(); ++i) {
        const Vec3f& p = kPyramid[i];
        w.value("float", 0.5).value(coord_type, p.x);
        w.value("uchar", static_cast<double>(i % 3));
        for (std::size_t t = 0; t < i % 3; ++t) {
            w.value("short", -1.0);
        }
        w.value(coord_type, p.y).value("uchar", 255).value(coord_type, p.z);
        w.value("double", 0.25).end_line();
    }
    w.value("int", 1).value(count_type, 4);
    for (int idx : {0, 1, 2, 3}) {
        w.value(index_type, idx);
    }
    w.value("uchar", 2).value("float", 0.5).value("float", 0.75).end_line();
    w.value("int", 2).value(count_type, 3);
    for (int idx : {4, 3, 2}) {
        w.value(index_type, idx);
    }
    w.value("uchar", 0).end_line();
    return header + w.data();
}

/// A plain triangle: three float vertices, one face.
[[nodiscard]] std::string make_triangle(const std::string& format) {
    std::string header = "ply\nformat " + format +
                         " 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 1\nproperty list uchar int "
                         "vertex_indices\nend_header\n";
    PlyWriter w(format);
    w.value("float", 0).value("float", 0).value("float", 0).end_line();
    w.value("float", 1).value("float", 0).value("float", 0).end_line();
    w.value("float", 0).value("float", 1).value("float", 0).end_line();
    w.value("uchar", 3).value("int", 0).value("int", 1).value("int", 2).end_line();
    return header + w.data();
}

const std::vector<std::string> kIntegerTypes{"char",  "int8",  "uchar",  "uint8",
                                             "short", "int16", "ushort", "uint16",
                                             "int",   "int32", "uint",   "uint32"};
const std::vector<std::string> kAllTypes{"char",   "int8",    "uchar",  "uint8",  "short", "int16",
                                         "ushort", "uint16",  "int",    "int32",  "uint",  "uint32",
                                         "float",  "float32", "double", "float64"};

TEST_F(PlyLoaderTest, EveryFormatAndScalarTypeGivesTheSamePyramid) {
    int n = 0;
    for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        for (std::size_t t = 0; t < kAllTypes.size(); ++t) {
            const std::string& count_type = kIntegerTypes[t % kIntegerTypes.size()];
            const std::string& index_type = kIntegerTypes[(t + 5) % kIntegerTypes.size()];
            SCOPED_TRACE(::testing::Message() << format << " coords " << kAllTypes[t] << " list "
                                              << count_type << " " << index_type);
            const auto path = write("pyramid" + std::to_string(n++) + ".ply",
                                    make_ply(format, kAllTypes[t], count_type, index_type));
            const auto mesh = load_ply(path);
            EXPECT_EQ(mesh.vertices, kPyramid);
            EXPECT_EQ(mesh.faces, kPyramidFaces);
        }
    }
}

TEST_F(PlyLoaderTest, VertexIndexIsAcceptedAsListName) {
    for (const std::string format : {"ascii", "binary_big_endian"}) {
        const auto mesh = load_ply(
            write(format + ".ply", make_ply(format, "float", "uchar", "int", "vertex_index")));
        EXPECT_EQ(mesh.faces, kPyramidFaces);
    }
}

TEST_F(PlyLoaderTest, AsciiWithFacesBeforeVerticesAndCrLf) {
    const auto mesh = load_ply(write("crlf.ply",
                                     "ply\r\n"
                                     "format ascii 1.0\r\n"
                                     "Created by an exporter that forgot the comment keyword\r\n"
                                     "element face 2\r\n"
                                     "property list uchar uint vertex_indices\r\n"
                                     "element vertex 4\r\n"
                                     "property float x\r\nproperty float y\r\nproperty float z\r\n"
                                     "end_header\r\n"
                                     "3 0 1 2\r\n"
                                     "3 2 3 0\r\n"
                                     "0 0 0\r\n1 0 0\r\n1 1 0\r\n0.5 -1.25e1 2\r\n"));
    ASSERT_EQ(mesh.vertices.size(), 4u);
    EXPECT_EQ(mesh.vertices[3], Vec3f(0.5f, -12.5f, 2.0f));
    EXPECT_EQ(mesh.faces, (std::vector<Face>{{0, 1, 2}, {2, 3, 0}}));
}

TEST_F(PlyLoaderTest, ElementWithoutPropertiesTakesNoSpaceWhateverItsCount) {
    std::string bytes = make_triangle("binary_little_endian");
    bytes.insert(bytes.find("element vertex"), "element nothing 18446744073709551615\n");
    const auto mesh = load_ply(write("empty_element.ply", bytes));
    EXPECT_EQ(mesh.faces, (std::vector<Face>{{0, 1, 2}}));
}

TEST_F(PlyLoaderTest, DegenerateFacesAreKeptInOrder) {
    const auto mesh = load_ply(write("degenerate.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 3\n"
                                     "property float x\nproperty float y\nproperty float z\n"
                                     "element face 3\nproperty list uchar int vertex_indices\n"
                                     "end_header\n0 0 0\n1 0 0\n0 1 0\n"
                                     "3 0 0 0\n3 0 1 2\n4 2 2 1 1\n"));
    EXPECT_EQ(mesh.faces, (std::vector<Face>{{0, 0, 0}, {0, 1, 2}, {2, 2, 1}, {2, 1, 1}}));
}

TEST_F(PlyLoaderTest, TruncatedDataReportsHowFarItGot) {
    const std::string binary = make_triangle("binary_little_endian");
    const std::size_t header_end = binary.find("end_header\n") + 11;
    expect_error(binary.substr(0, header_end + 12 + 5), "expected 3 vertices, file ends after 1");
    expect_error(binary.substr(0, header_end + 36 + 3), "expected 1 faces, file ends after 0");
    expect_error(binary.substr(0, binary.size() - 1), "expected 1 faces, file ends after 0");
    const std::string ascii = make_triangle("ascii");
    expect_error(ascii.substr(0, ascii.find("0.000000 1.000000")),
                 "expected 3 vertices, file ends after 2");
    // Truncation inside an element that is skipped is reported too.
    const std::string pyramid = make_ply("binary_big_endian", "float", "uchar", "int");
    expect_error(pyramid.substr(0, pyramid.find("end_header\n") + 11 + 4),
                 "expected 2 'edge' elements, file ends after 0");
}

TEST_F(PlyLoaderTest, BrokenHeadersThrow) {
    const std::string good = make_triangle("ascii");
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        s.replace(s.find(from), from.size(), to);
        return s;
    };
    expect_error(replaced("ply\n", "plx\n"), "broken.ply:1: not a PLY file");
    expect_error("", "broken.ply:1: not a PLY file");
    expect_error(replaced("ascii", "binary_middle_endian"),
                 "broken.ply:2: unknown PLY format 'binary_middle_endian'");
    expect_error(replaced("property float y", "property float128 y"),
                 "broken.ply:5: unknown property type 'float128'");
    expect_error(replaced("list uchar int", "list float int"), "list count type");
    expect_error(replaced("list uchar int", "list uchar float"), "must be a list of integers");
    expect_error(replaced("property list uchar int vertex_indices", "property int vertex_indices"),
                 "must be a list of integers");
    expect_error(replaced("end_header\n", "end_heade\n"), "no 'end_header'");
    expect_error(replaced("element vertex 3", "element vertex three"), "broken.ply:3: expected");
    expect_error(replaced("format ascii 1.0\n", ""), "no 'format' line");
    expect_error(replaced("element vertex 3\n", ""), "property declared before any element");
    expect_error(replaced("property float x", "property float u"), "no property 'x'");
    expect_error(replaced("property float z", "property list uchar float z"), "'z' is a list");
    expect_error(replaced("element face 1", "element face 0"), "no triangles");
    expect_error(replaced("element face 1", "element polygon 1"), "no triangles");
    expect_error(replaced("element vertex 3", "element point 3"), "no 'vertex' element");
    expect_error(replaced("vertex_indices", "corners"), "no 'vertex_indices' list");
}

TEST_F(PlyLoaderTest, BrokenDataThrowsWithLineForAscii) {
    const std::string good = make_triangle("ascii");
    // Data starts on line 10: vertices on lines 10-12, the face on line 13.
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        s.replace(s.rfind(from), from.size(), to);
        return s;
    };
    expect_error(replaced("3 0 1 2", "3 0 1 3"),
                 "broken.ply:13: face 0: vertex index 3 is out of range (3 vertices)");
    expect_error(replaced("3 0 1 2", "3 0 -1 2"), "broken.ply:13: face 0: vertex index -1");
    expect_error(replaced("3 0 1 2", "2 0 1"), "broken.ply:13: face 0 has 2 vertices");
    expect_error(replaced("1.000000 0.000000 0.000000", "1.000000 0.0.0 0.000000"),
                 "broken.ply:11: malformed number '0.0.0'");
    expect_error(replaced("3 0 1 2", "3 0 1 x"), "broken.ply:13: malformed integer 'x'");
    expect_error(replaced("1.000000 0.000000 0.000000", "1.000000 nan 0.000000"),
                 "broken.ply:11: vertex 1: coordinate is not a finite float");
    // Whole numbers written as reals are accepted for counts and indices.
    EXPECT_EQ(load_ply(write("reals.ply", replaced("3 0 1 2", "3.0 0 1.0 2"))).faces,
              (std::vector<Face>{{0, 1, 2}}));
}

TEST_F(PlyLoaderTest, BrokenBinaryDataThrows) {
    std::string bytes = make_triangle("binary_little_endian");
    std::string out_of_range = bytes;
    const std::int32_t big_index = 7;
    std::memcpy(out_of_range.data() + out_of_range.size() - 4, &big_index, 4);
    if (std::endian::native == std::endian::little) {
        expect_error(out_of_range, "face 0: vertex index 7 is out of range (3 vertices)");
    }
    std::string nan_vertex = bytes;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(nan_vertex.data() + nan_vertex.find("end_header\n") + 11 + 16, &nan, 4);
    expect_error(nan_vertex, "vertex 1: coordinate is not a finite float");
}

TEST_F(PlyLoaderTest, EveryTruncationAndByteFlipThrowsInputErrorOrLoads) {
    std::mt19937 rng(12345);
    for (const std::string format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        SCOPED_TRACE(format);
        const std::string bytes = make_ply(format, "double", "uchar", "uint");
        test::load_every_truncation(bytes, [&](const std::string& cut) {
            // Only cutting trailing white space leaves a complete file.
            EXPECT_EQ(load_ply(write("cut.ply", cut)).faces, kPyramidFaces);
            EXPECT_EQ(format, "ascii");
            EXPECT_GE(cut.size(), bytes.size() - 2);
        });
        test::load_random_byte_flips(bytes, rng, 300, [&](const std::string& corrupt) {
            const auto mesh = load_ply(write("flip.ply", corrupt));
            EXPECT_NO_THROW(mesh.check_indices("flip.ply"));
        });
    }
}

TEST_F(PlyLoaderTest, MissingFileThrowsWithName) {
    test::expect_input_error(load_ply, dir_ / "absent.ply");
}

TEST_F(PlyLoaderTest, LoadMeshDispatchesPly) {
    EXPECT_EQ(load_mesh(write("tri.Ply", make_triangle("ascii"))).triangle_count(), 1u);
}

TEST(PlyLoaderSharedData, CubeQuadsAreFanTriangulated) {
    const fs::path path = test::shared_mesh("ply/cube.ply");
    BEAMTRACE_REQUIRE_FILE(path);
    const auto mesh = load_ply(path);
    ASSERT_EQ(mesh.vertices.size(), 8u);
    EXPECT_EQ(mesh.vertices[1], Vec3f(0.0f, 0.0f, 1.0f));
    EXPECT_EQ(mesh.vertices[6], Vec3f(1.0f, 1.0f, 1.0f));
    ASSERT_EQ(mesh.triangle_count(), 12u);
    EXPECT_EQ(mesh.faces[0], (Face{0, 1, 2}));  // "4 0 1 2 3"
    EXPECT_EQ(mesh.faces[1], (Face{0, 2, 3}));
    EXPECT_EQ(mesh.faces[2], (Face{7, 6, 5}));   // "4 7 6 5 4"
    EXPECT_EQ(mesh.faces[11], (Face{3, 4, 0}));  // "4 3 7 4 0"
}

TEST(PlyLoaderSharedData, RealFilesHaveTheExpectedCounts) {
    BEAMTRACE_REQUIRE_FILE(test::shared_mesh(""));
    struct Case {
        const char* file;
        std::size_t triangles;
        std::size_t vertices;
    };
    for (const Case& c :
         {Case{"ply/cube_binary.ply", 12, 8}, Case{"ply/Wuson.ply", 3732, 11184},
          Case{"medium/horse.ply", 96966, 48485}, Case{"medium/dragon-100k.ply", 100000, 50002},
          Case{"large/dem_hd_heightfield.ply", 1480960, 742233}}) {
        SCOPED_TRACE(c.file);
        const auto mesh = load_ply(test::shared_mesh(c.file));
        EXPECT_EQ(mesh.triangle_count(), c.triangles);
        EXPECT_EQ(mesh.vertices.size(), c.vertices);
    }
}

TEST(PlyLoaderSharedData, HeightfieldSpansTheDemExtent) {
    const fs::path path = test::shared_mesh("large/dem_hd_heightfield.ply");
    BEAMTRACE_REQUIRE_FILE(path);
    const Aabb box = load_ply(path).bounds();
    // 1041 x 713 pixel centres, 25 m apart; elevations 34-581 m.
    EXPECT_NEAR(box.extent().x, 1040.0f * 25.0f, 1.0f);
    EXPECT_NEAR(box.extent().y, 712.0f * 25.0f, 1.0f);
    EXPECT_GT(box.lo.z, 30.0f);
    EXPECT_LT(box.hi.z, 590.0f);
}

}  // namespace
}  // namespace beamtrace
