// STL, binary or ASCII. Binary is recognised by its size (84 + 50 n bytes), so that binary files
// whose 80-byte header starts with "solid" are not mistaken for ASCII.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "text/file_bytes.hpp"
#include "text/text_scan.hpp"

namespace beamtrace {
namespace {

constexpr std::size_t kHeaderBytes = 84;  // 80-byte comment + uint32 facet count
constexpr std::size_t kFacetBytes = 50;   // normal, 3 vertices (12 float32) + uint16 attribute

template <typename T>
[[nodiscard]] T load_le(const char* p) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, p, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) {
        std::reverse(bytes, bytes + sizeof(T));
    }
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
}

void add_triangle(TriangleMesh& mesh, const std::array<Vec3f, 3>& corners) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.insert(mesh.vertices.end(), corners.begin(), corners.end());
    mesh.faces.push_back({base, base + 1, base + 2});
}

[[nodiscard]] std::uint64_t binary_facet_count(std::string_view bytes) {
    return load_le<std::uint32_t>(bytes.data() + 80);
}

/// ASCII if it starts with "solid" and its first bytes hold no NUL (binary files almost always
/// have one there: the facet count's high byte or the padding of the 80-byte comment).
[[nodiscard]] bool looks_ascii(std::string_view bytes) {
    std::size_t start = 0;
    while (start < bytes.size() && (detail::is_blank(bytes[start]) || bytes[start] == '\n')) {
        ++start;
    }
    if (bytes.size() - start < 5 || !detail::iequals(bytes.substr(start, 5), "solid")) {
        return false;
    }
    return bytes.substr(0, kHeaderBytes).find('\0') == std::string_view::npos;
}

[[nodiscard]] TriangleMesh parse_binary(std::string_view bytes, const std::string& path) {
    if (bytes.size() < kHeaderBytes) {
        throw InputError(path, "file too short for a binary STL (" + std::to_string(bytes.size()) +
                                   " bytes, the header alone is 84) and not ASCII STL");
    }
    const std::uint64_t count = binary_facet_count(bytes);
    const std::uint64_t present = (bytes.size() - kHeaderBytes) / kFacetBytes;
    if (present < count) {
        throw InputError(path, "truncated binary STL: expected " + std::to_string(count) +
                                   " facets, file ends after " + std::to_string(present));
    }
    if (count == 0) {
        throw InputError(path, "no triangles (binary STL with 0 facets)");
    }
    if (3 * count > std::numeric_limits<std::uint32_t>::max()) {
        throw InputError(path, "too many facets for 32-bit indices");
    }
    TriangleMesh mesh;
    mesh.vertices.reserve(static_cast<std::size_t>(3 * count));
    mesh.faces.reserve(static_cast<std::size_t>(count));
    for (std::uint64_t i = 0; i < count; ++i) {
        const char* facet = bytes.data() + kHeaderBytes + i * kFacetBytes;
        std::array<Vec3f, 3> corners;
        for (std::size_t c = 0; c < 3; ++c) {
            const char* p = facet + 12 * (c + 1);  // skip the normal
            corners[c] = {load_le<float>(p), load_le<float>(p + 4), load_le<float>(p + 8)};
        }
        add_triangle(mesh, corners);
    }
    return mesh;
}

/// solid NAME { facet normal N N N outer loop (vertex X Y Z)x3 endloop endfacet } endsolid NAME,
/// repeated for each solid. Keywords are case-insensitive.
class AsciiStlParser {
  public:
    AsciiStlParser(std::string_view text, const std::string& path) : cur_(text), path_(path) {}

    TriangleMesh parse() {
        while (!cur_.at_end()) {
            expect("solid");
            cur_.skip_line();  // the solid's name
            while (true) {
                const std::string_view token = cur_.next();
                if (detail::iequals(token, "endsolid")) {
                    cur_.skip_line();
                    break;
                }
                if (!detail::iequals(token, "facet")) {
                    unexpected(token, "'facet' or 'endsolid'");
                }
                parse_facet();
            }
        }
        if (mesh_.faces.empty()) {
            throw InputError(path_, "no triangles (ASCII STL without facets)");
        }
        return std::move(mesh_);
    }

  private:
    void parse_facet() {
        expect("normal");
        Vec3f normal;
        read_vec(normal);  // ignored: recomputed from the vertices where needed
        expect("outer");
        expect("loop");
        std::array<Vec3f, 3> corners;
        for (auto& corner : corners) {
            expect("vertex");
            read_vec(corner);
        }
        expect("endloop");
        expect("endfacet");
        if (mesh_.vertices.size() + 3 > std::numeric_limits<std::uint32_t>::max()) {
            throw InputError(path_, cur_.line(), "too many facets for 32-bit indices");
        }
        add_triangle(mesh_, corners);
    }

    void read_vec(Vec3f& v) {
        for (std::size_t a = 0; a < 3; ++a) {
            const std::string_view token = cur_.next();
            double value = 0.0;
            if (token.empty()) {
                unexpected(token, "a number");
            }
            if (!detail::parse_number(token, value)) {
                throw InputError(path_, cur_.line(),
                                 "malformed number '" + std::string(token) + "'");
            }
            if (!detail::to_float_coordinate(value, v[a])) {
                throw InputError(path_, cur_.line(),
                                 "coordinate '" + std::string(token) + "' is not a finite float");
            }
        }
    }

    void expect(std::string_view keyword) {
        const std::string_view token = cur_.next();
        if (!detail::iequals(token, keyword)) {
            unexpected(token, "'" + std::string(keyword) + "'");
        }
    }

    [[noreturn]] void unexpected(std::string_view token, const std::string& expected) const {
        if (token.empty()) {
            throw InputError(path_, cur_.line(), "unexpected end of file, expected " + expected);
        }
        throw InputError(path_, cur_.line(),
                         "expected " + expected + ", found '" + std::string(token) + "'");
    }

    detail::TextCursor cur_;
    const std::string& path_;
    TriangleMesh mesh_;
};

}  // namespace

TriangleMesh load_stl(const std::filesystem::path& path) {
    const std::string name = path.string();
    const std::string bytes = detail::read_file_bytes(path);
    const bool exact_binary_size =
        bytes.size() >= kHeaderBytes &&
        kHeaderBytes + kFacetBytes * binary_facet_count(bytes) == bytes.size();
    TriangleMesh mesh = !exact_binary_size && looks_ascii(bytes)
                            ? AsciiStlParser(bytes, name).parse()
                            : parse_binary(bytes, name);
    mesh.check_indices(name.c_str());
    return mesh;
}

}  // namespace beamtrace
