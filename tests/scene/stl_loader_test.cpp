#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

class StlLoaderTest : public test::TempDirTest {
  protected:
    /// Loading `bytes` must throw InputError naming the file, with `expected` in the message.
    void expect_error(const std::string& bytes, const std::string& expected) const {
        test::expect_input_error(load_stl, write("broken.stl", bytes), expected);
    }
};

/// A binary STL with the given 80-byte comment (padded with `pad`) and facets.
[[nodiscard]] std::string make_binary(const std::string& comment,
                                      const std::vector<std::array<Vec3f, 3>>& facets,
                                      char pad = '\0') {
    std::string out = comment;
    out.resize(80, pad);
    test::append_bytes(out, static_cast<std::uint32_t>(facets.size()));
    for (const auto& f : facets) {
        for (float n : {0.0f, 0.0f, 1.0f}) {
            test::append_bytes(out, n);
        }
        for (const Vec3f& v : f) {
            test::append_bytes(out, v.x);
            test::append_bytes(out, v.y);
            test::append_bytes(out, v.z);
        }
        test::append_bytes(out, std::uint16_t{0});
    }
    return out;
}

const std::vector<std::array<Vec3f, 3>> kTwoFacets{
    {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
    {{{1.5f, -2, 3}, {1.5f, -2, 3}, {4, 5, 6.25f}}},  // degenerate, must be kept
};

void expect_two_facets(const TriangleMesh& mesh) {
    ASSERT_EQ(mesh.triangle_count(), 2u);
    ASSERT_EQ(mesh.vertices.size(), 6u);
    for (std::size_t f = 0; f < 2; ++f) {
        for (std::size_t c = 0; c < 3; ++c) {
            EXPECT_EQ(mesh.vertices[mesh.faces[f][c]], kTwoFacets[f][c]) << f << " " << c;
        }
    }
}

constexpr const char* kAsciiTwoFacets =
    "solid two\n"
    "  facet normal 0 0 1\n"
    "    outer loop\n"
    "      vertex 0 0 0\n"
    "      vertex 1 0 0\n"
    "      vertex 0 1 0\n"
    "    endloop\n"
    "  endfacet\n"
    "  facet normal 0 0 0\n"
    "    outer loop\n"
    "      vertex 1.5 -2 3\n"
    "      vertex 1.5e0 -2.0 +3\n"
    "      vertex 4 5 6.25\n"
    "    endloop\n"
    "  endfacet\n"
    "endsolid two\n";

TEST_F(StlLoaderTest, AsciiFacetsInOrderWithDegenerateKept) {
    expect_two_facets(load_stl(write("two.stl", kAsciiTwoFacets)));
}

TEST_F(StlLoaderTest, AsciiKeywordsAreCaseInsensitiveAndCrLfIsFine) {
    std::string text = kAsciiTwoFacets;
    std::string upper;
    for (char c : text) {
        if (c == '\n') {
            upper += "\r\n";
        } else {
            upper += static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
        }
    }
    expect_two_facets(load_stl(write("upper.stl", upper)));
}

TEST_F(StlLoaderTest, BinaryFacetsInOrder) {
    expect_two_facets(load_stl(write("two_bin.stl", make_binary("plain binary", kTwoFacets))));
}

TEST_F(StlLoaderTest, BinaryWhoseCommentStartsWithSolidIsStillBinary) {
    // Padded with spaces: only the size (84 + 50 n) tells it from ASCII.
    expect_two_facets(
        load_stl(write("solid_bin.stl", make_binary("solid exported by CAD", kTwoFacets, ' '))));
    // With trailing bytes the size does not match, but the NUL bytes of the header give it away.
    expect_two_facets(load_stl(
        write("solid_pad.stl", make_binary("solid exported by CAD", kTwoFacets) + "extra")));
}

TEST_F(StlLoaderTest, TruncatedBinaryThrows) {
    const std::string bytes = make_binary("binary", kTwoFacets);
    expect_error(bytes.substr(0, bytes.size() - 1),
                 "truncated binary STL: expected 2 facets, file ends after 1");
    const std::string solid = make_binary("solid but binary", kTwoFacets);
    expect_error(solid.substr(0, 84 + 20), "expected 2 facets, file ends after 0");
    expect_error(bytes.substr(0, 40), "too short for a binary STL");
    expect_error("", "too short");
    expect_error(make_binary("binary", {}), "no triangles");
}

TEST_F(StlLoaderTest, MalformedAsciiThrowsWithLine) {
    const std::string good = kAsciiTwoFacets;
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        s.replace(s.find(from), from.size(), to);
        return s;
    };
    expect_error(replaced("vertex 1 0 0", "vertex 1 0 zero"), "broken.stl:5: malformed number");
    expect_error(replaced("vertex 1 0 0", "vertex 1 0"), "broken.stl:6: malformed number 'vertex'");
    expect_error(replaced("    endloop\n", ""),
                 "broken.stl:7: expected 'endloop', found 'endfacet'");
    expect_error(replaced("outer loop", "outer"), "broken.stl:4: expected 'loop', found 'vertex'");
    expect_error(replaced("  facet normal 0 0 0", "  facets normal 0 0 0"),
                 "broken.stl:9: expected 'facet' or 'endsolid', found 'facets'");
    expect_error(good.substr(0, good.find("vertex 4")),
                 "unexpected end of file, expected 'vertex'");
    expect_error(replaced("endsolid two\n", ""), "unexpected end of file");
    expect_error(good + "garbage\n", "broken.stl:17: expected 'solid', found 'garbage'");
    expect_error("solid empty\nendsolid empty\n", "no triangles");
    expect_error(replaced("vertex 1 0 0", "vertex 1 0 1e60"), "broken.stl:5: coordinate");
}

TEST_F(StlLoaderTest, EveryTruncationAndByteFlipThrowsInputErrorOrLoads) {
    std::mt19937 rng(6789);
    for (const std::string& bytes :
         {std::string(kAsciiTwoFacets), make_binary("solid", kTwoFacets, ' ')}) {
        test::load_every_truncation(bytes, [&](const std::string& cut) {
            // Only cutting the name after "endsolid" leaves a complete file.
            expect_two_facets(load_stl(write("cut.stl", cut)));
            EXPECT_GE(cut.size(), bytes.find("endsolid") + 8);
        });
        test::load_random_byte_flips(bytes, rng, 300, [&](const std::string& corrupt) {
            const auto mesh = load_stl(write("flip.stl", corrupt));
            EXPECT_EQ(mesh.vertices.size(), 3 * mesh.triangle_count());
        });
    }
}

TEST_F(StlLoaderTest, MissingFileThrowsWithName) {
    test::expect_input_error(load_stl, dir_ / "absent.stl");
}

TEST_F(StlLoaderTest, LoadMeshDispatchesStl) {
    EXPECT_EQ(load_mesh(write("two.STL", kAsciiTwoFacets)).triangle_count(), 2u);
}

TEST(StlLoaderSharedData, SeveralAndEmptySolids) {
    const fs::path two = test::shared_mesh("stl/triangle_with_two_solids.stl");
    const fs::path empty = test::shared_mesh("stl/triangle_with_empty_solid.stl");
    BEAMTRACE_REQUIRE_FILE(two);
    BEAMTRACE_REQUIRE_FILE(empty);
    const auto mesh = load_stl(two);
    ASSERT_EQ(mesh.triangle_count(), 2u);
    EXPECT_EQ(mesh.vertices[mesh.faces[0][0]], Vec3f(1.0f, 1.0f, 0.0f));
    EXPECT_EQ(mesh.vertices[mesh.faces[1][0]], Vec3f(3.0f, 3.0f, 0.0f));
    EXPECT_EQ(mesh.vertices[mesh.faces[1][2]], Vec3f(0.0f, 2.0f, 0.0f));
    const auto single = load_stl(empty);
    ASSERT_EQ(single.triangle_count(), 1u);
    EXPECT_EQ(single.vertices[single.faces[0][1]], Vec3f(-1.0f, 1.0f, 0.0f));
}

TEST(StlLoaderSharedData, RealFilesHaveTheExpectedTriangleCounts) {
    BEAMTRACE_REQUIRE_FILE(test::shared_mesh(""));
    struct Case {
        const char* file;
        std::size_t triangles;
    };
    for (const Case& c : {Case{"stl/Spider_binary.stl", 1368}, Case{"stl/Spider_ascii.stl", 1368},
                          Case{"stl/Wuson.stl", 3732}, Case{"stl/sphereWithHole.stl", 285}}) {
        SCOPED_TRACE(c.file);
        const auto mesh = load_stl(test::shared_mesh(c.file));
        EXPECT_EQ(mesh.triangle_count(), c.triangles);
        EXPECT_EQ(mesh.vertices.size(), 3 * c.triangles);
    }
}

TEST(StlLoaderSharedData, AsciiAndBinarySpiderAgree) {
    const fs::path ascii_path = test::shared_mesh("stl/Spider_ascii.stl");
    const fs::path binary_path = test::shared_mesh("stl/Spider_binary.stl");
    BEAMTRACE_REQUIRE_FILE(ascii_path);
    BEAMTRACE_REQUIRE_FILE(binary_path);
    const auto ascii = load_stl(ascii_path);
    const auto binary = load_stl(binary_path);
    ASSERT_EQ(ascii.triangle_count(), binary.triangle_count());
    // The first facet of Spider_ascii.stl.
    EXPECT_NEAR(ascii.vertices[ascii.faces[0][0]].x, 0.907128f, 1e-6f);
    EXPECT_NEAR(ascii.vertices[ascii.faces[0][1]].y, 1.111567f, 1e-6f);
    EXPECT_NEAR(ascii.vertices[ascii.faces[0][2]].z, 0.284519f, 1e-6f);
    for (std::size_t f = 0; f < ascii.triangle_count(); ++f) {
        for (std::size_t c = 0; c < 3; ++c) {
            const Vec3f a = ascii.vertices[ascii.faces[f][c]];
            const Vec3f b = binary.vertices[binary.faces[f][c]];
            ASSERT_NEAR(a.x, b.x, 1e-4f) << "facet " << f;
            ASSERT_NEAR(a.y, b.y, 1e-4f) << "facet " << f;
            ASSERT_NEAR(a.z, b.z, 1e-4f) << "facet " << f;
        }
    }
}

}  // namespace
}  // namespace beamtrace
