// PLY (Stanford polygon file): ascii and binary in both byte orders, any element order.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "scene/detail/ply_header.hpp"
#include "scene/detail/ply_source.hpp"
#include "text/file_bytes.hpp"
#include "text/text_scan.hpp"

namespace beamtrace {
namespace {

using detail::PlyElement;
using detail::PlyFormat;
using detail::PlyHeader;
using detail::PlyProperty;

/// Where the mesh lives in the file, checked against the header before any data is read.
struct PlyLayout {
    const PlyElement* vertex = nullptr;
    std::array<std::size_t, 3> xyz{};  ///< property indices of x, y, z in `vertex`
    const PlyElement* face = nullptr;
    std::size_t indices = 0;  ///< property index of the vertex index list in `face`
};

[[nodiscard]] PlyLayout find_layout(const PlyHeader& header, const std::string& path) {
    PlyLayout layout;
    layout.vertex = header.find("vertex");
    if (layout.vertex == nullptr) {
        throw InputError(path, "no 'vertex' element in the header");
    }
    if (layout.vertex->count > std::numeric_limits<std::uint32_t>::max()) {
        throw InputError(path, "too many vertices for 32-bit indices");
    }
    constexpr std::array<std::string_view, 3> kAxes{"x", "y", "z"};
    for (std::size_t a = 0; a < 3; ++a) {
        layout.xyz[a] = layout.vertex->find(kAxes[a]);
        if (layout.xyz[a] == PlyElement::npos) {
            throw InputError(
                path, "the 'vertex' element has no property '" + std::string(kAxes[a]) + "'");
        }
        if (layout.vertex->properties[layout.xyz[a]].is_list) {
            throw InputError(path, "vertex property '" + std::string(kAxes[a]) +
                                       "' is a list, expected a scalar");
        }
    }
    layout.face = header.find("face");
    if (layout.face == nullptr || layout.face->count == 0) {
        throw InputError(path, "no triangles (no 'face' element or it is empty)");
    }
    layout.indices = layout.face->find("vertex_indices");
    if (layout.indices == PlyElement::npos) {
        layout.indices = layout.face->find("vertex_index");
    }
    if (layout.indices == PlyElement::npos) {
        throw InputError(path, "the 'face' element has no 'vertex_indices' list");
    }
    const PlyProperty& list = layout.face->properties[layout.indices];
    if (!list.is_list || !detail::ply_type_is_integer(list.type)) {
        throw InputError(path, "face property '" + list.name + "' must be a list of integers");
    }
    return layout;
}

[[nodiscard]] std::string plural(const std::string& element_name) {
    if (element_name == "vertex") {
        return "vertices";
    }
    if (element_name == "face") {
        return "faces";
    }
    return "'" + element_name + "' elements";
}

/// Reads the data section element by element with a PlyAsciiSource or PlyBinarySource.
template <typename Source>
class PlyBodyReader {
  public:
    PlyBodyReader(Source& source, const PlyLayout& layout, TriangleMesh& mesh)
        : src_(source), layout_(layout), mesh_(mesh) {}

    void read(const PlyHeader& header) {
        for (const PlyElement& element : header.elements) {
            if (&element == layout_.vertex) {
                read_vertices(element, header.format);
            } else if (&element == layout_.face) {
                read_faces(element, header.format);
            } else {
                skip_element(element);
            }
        }
    }

  private:
    [[noreturn]] void truncated(const PlyElement& element, std::uint64_t done) const {
        src_.fail("expected " + std::to_string(element.count) + " " + plural(element.name) +
                  ", file ends after " + std::to_string(done));
    }

    [[nodiscard]] std::size_t reserve_count(const PlyElement& element, PlyFormat format) const {
        const std::uint64_t fit = src_.size() / element.min_instance_bytes(format);
        return static_cast<std::size_t>(std::min<std::uint64_t>(element.count, fit));
    }

    [[nodiscard]] bool skip_property(const PlyProperty& property) {
        if (!property.is_list) {
            return src_.skip(property.type);
        }
        std::int64_t n = 0;
        if (!src_.read_integer(property.count_type, n)) {
            return false;
        }
        if (n < 0) {
            src_.fail("negative list length " + std::to_string(n) + " for '" + property.name + "'");
        }
        for (std::int64_t k = 0; k < n; ++k) {
            if (!src_.skip(property.type)) {
                return false;
            }
        }
        return true;
    }

    void read_vertices(const PlyElement& element, PlyFormat format) {
        std::vector<int> axis_of(element.properties.size(), -1);
        for (std::size_t a = 0; a < 3; ++a) {
            axis_of[layout_.xyz[a]] = static_cast<int>(a);
        }
        mesh_.vertices.reserve(reserve_count(element, format));
        for (std::uint64_t i = 0; i < element.count; ++i) {
            std::array<double, 3> xyz{};
            for (std::size_t k = 0; k < element.properties.size(); ++k) {
                const PlyProperty& property = element.properties[k];
                const bool ok =
                    axis_of[k] >= 0
                        ? src_.read_real(property.type, xyz[static_cast<std::size_t>(axis_of[k])])
                        : skip_property(property);
                if (!ok) {
                    truncated(element, i);
                }
            }
            Vec3f v;
            for (std::size_t a = 0; a < 3; ++a) {
                if (!detail::to_float_coordinate(xyz[a], v[a])) {
                    src_.fail("vertex " + std::to_string(i) + ": coordinate is not a finite float");
                }
            }
            mesh_.vertices.push_back(v);
        }
    }

    void read_faces(const PlyElement& element, PlyFormat format) {
        const auto vertex_count = static_cast<std::int64_t>(layout_.vertex->count);
        mesh_.faces.reserve(reserve_count(element, format));
        for (std::uint64_t i = 0; i < element.count; ++i) {
            for (std::size_t k = 0; k < element.properties.size(); ++k) {
                const PlyProperty& property = element.properties[k];
                if (k != layout_.indices) {
                    if (!skip_property(property)) {
                        truncated(element, i);
                    }
                    continue;
                }
                std::int64_t n = 0;
                if (!src_.read_integer(property.count_type, n)) {
                    truncated(element, i);
                }
                if (n < 3) {
                    src_.fail("face " + std::to_string(i) + " has " + std::to_string(n) +
                              " vertices, needs at least 3");
                }
                polygon_.clear();
                for (std::int64_t j = 0; j < n; ++j) {
                    std::int64_t index = 0;
                    if (!src_.read_integer(property.type, index)) {
                        truncated(element, i);
                    }
                    if (index < 0 || index >= vertex_count) {
                        src_.fail("face " + std::to_string(i) + ": vertex index " +
                                  std::to_string(index) + " is out of range (" +
                                  std::to_string(vertex_count) + " vertices)");
                    }
                    polygon_.push_back(static_cast<std::uint32_t>(index));
                }
                for (std::size_t j = 1; j + 1 < polygon_.size(); ++j) {
                    mesh_.faces.push_back({polygon_[0], polygon_[j], polygon_[j + 1]});
                }
            }
        }
    }

    void skip_element(const PlyElement& element) {
        if (element.properties.empty()) {
            return;  // nothing stored, whatever the count says
        }
        for (std::uint64_t i = 0; i < element.count; ++i) {
            for (const PlyProperty& property : element.properties) {
                if (!skip_property(property)) {
                    truncated(element, i);
                }
            }
        }
    }

    Source& src_;
    const PlyLayout& layout_;
    TriangleMesh& mesh_;
    std::vector<std::uint32_t> polygon_;
};

template <typename Source>
void read_body(Source& source, const PlyHeader& header, const PlyLayout& layout,
               TriangleMesh& mesh) {
    PlyBodyReader<Source>(source, layout, mesh).read(header);
}

}  // namespace

TriangleMesh load_ply(const std::filesystem::path& path) {
    const std::string name = path.string();
    const std::string bytes = detail::read_file_bytes(path);
    const PlyHeader header = detail::parse_ply_header(bytes, name);
    const PlyLayout layout = find_layout(header, name);
    const std::string_view data = std::string_view(bytes).substr(header.data_offset);

    TriangleMesh mesh;
    if (header.format == PlyFormat::ascii) {
        detail::PlyAsciiSource source(data, header.data_line, name);
        read_body(source, header, layout, mesh);
    } else {
        detail::PlyBinarySource source(data, header.format == PlyFormat::binary_big_endian, name);
        read_body(source, header, layout, mesh);
    }
    mesh.check_indices(name.c_str());
    return mesh;
}

}  // namespace beamtrace
