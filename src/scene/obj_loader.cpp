// Wavefront OBJ: only `v` (positions) and `f` (polygons) matter for a triangle mesh.
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "text/file_bytes.hpp"
#include "text/text_scan.hpp"

namespace beamtrace {
namespace {

/// Splits a line into blank-separated tokens without allocating.
class LineTokens {
  public:
    explicit LineTokens(std::string_view line) : line_(line) {}
    [[nodiscard]] std::string_view next() {
        while (pos_ < line_.size() && detail::is_blank(line_[pos_])) {
            ++pos_;
        }
        const std::size_t start = pos_;
        while (pos_ < line_.size() && !detail::is_blank(line_[pos_])) {
            ++pos_;
        }
        return line_.substr(start, pos_ - start);
    }

  private:
    std::string_view line_;
    std::size_t pos_ = 0;
};

class ObjParser {
  public:
    explicit ObjParser(std::string path) : path_(std::move(path)) {}

    void parse_line(std::string_view line, long line_no) {
        if (const auto hash = line.find('#'); hash != std::string_view::npos) {
            line = line.substr(0, hash);
        }
        LineTokens tokens(line);
        const std::string_view keyword = tokens.next();
        if (keyword == "v") {
            parse_vertex(tokens, line_no);
        } else if (keyword == "f") {
            parse_face(tokens, line_no);
        }
        // vt vn vp o g s usemtl mtllib l p and unknown statements carry no triangles.
    }

    [[nodiscard]] TriangleMesh finish() {
        if (mesh_.faces.empty()) {
            throw InputError(path_, "no triangles (the file has no 'f' statements)");
        }
        mesh_.check_indices(path_.c_str());
        return std::move(mesh_);
    }

  private:
    void parse_vertex(LineTokens& tokens, long line_no) {
        Vec3f v;
        for (std::size_t axis = 0; axis < 3; ++axis) {
            const std::string_view token = tokens.next();
            if (token.empty()) {
                throw InputError(path_, line_no,
                                 "vertex needs 3 coordinates, found " + std::to_string(axis));
            }
            double value = 0.0;
            if (!detail::parse_number(token, value)) {
                throw InputError(path_, line_no, "malformed number '" + std::string(token) + "'");
            }
            if (!detail::to_float_coordinate(value, v[axis])) {
                throw InputError(path_, line_no,
                                 "coordinate '" + std::string(token) + "' is not a finite float");
            }
        }
        // An optional w and per-vertex colours may follow; they are ignored.
        if (mesh_.vertices.size() >= std::numeric_limits<std::uint32_t>::max()) {
            throw InputError(path_, line_no, "too many vertices for 32-bit indices");
        }
        mesh_.vertices.push_back(v);
    }

    void parse_face(LineTokens& tokens, long line_no) {
        polygon_.clear();
        for (std::string_view token = tokens.next(); !token.empty(); token = tokens.next()) {
            polygon_.push_back(resolve_index(token, line_no));
        }
        if (polygon_.size() < 3) {
            throw InputError(
                path_, line_no,
                "face has " + std::to_string(polygon_.size()) + " vertices, needs at least 3");
        }
        for (std::size_t i = 1; i + 1 < polygon_.size(); ++i) {
            mesh_.faces.push_back({polygon_[0], polygon_[i], polygon_[i + 1]});
        }
    }

    /// Turns `i`, `i/j`, `i//k` or `i/j/k` (1-based, or negative = relative) into a 0-based index.
    [[nodiscard]] std::uint32_t resolve_index(std::string_view token, long line_no) const {
        const std::string_view index_text = token.substr(0, token.find('/'));
        std::int64_t index = 0;
        if (!detail::parse_number(index_text, index)) {
            throw InputError(path_, line_no, "malformed face index '" + std::string(token) + "'");
        }
        const auto count = static_cast<std::int64_t>(mesh_.vertices.size());
        if (index == 0) {
            throw InputError(path_, line_no, "face index 0 is invalid (OBJ indices start at 1)");
        }
        const std::int64_t resolved = index > 0 ? index - 1 : count + index;
        if (resolved < 0 || resolved >= count) {
            throw InputError(path_, line_no,
                             "face index " + std::to_string(index) + " is out of range: " +
                                 std::to_string(count) + " vertices defined so far");
        }
        return static_cast<std::uint32_t>(resolved);
    }

    std::string path_;
    TriangleMesh mesh_;
    std::vector<std::uint32_t> polygon_;
};

[[nodiscard]] std::string_view strip_cr(std::string_view line) {
    if (!line.empty() && line.back() == '\r') {
        line.remove_suffix(1);
    }
    return line;
}

}  // namespace

TriangleMesh load_obj(const std::filesystem::path& path) {
    const std::string bytes = detail::read_file_bytes(path);
    const std::string_view text(bytes);
    ObjParser parser(path.string());

    std::string joined;  // a statement continued over several lines with a trailing backslash
    std::size_t pos = 0;
    long line_no = 0;
    auto next_line = [&]() {
        const std::size_t nl = text.find('\n', pos);
        const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
        const std::string_view line = strip_cr(text.substr(pos, end - pos));
        pos = end == text.size() ? end : end + 1;
        ++line_no;
        return line;
    };

    while (pos < text.size()) {
        std::string_view line = next_line();
        const long first_line = line_no;
        if (!line.empty() && line.back() == '\\') {
            joined.assign(line.substr(0, line.size() - 1));
            bool continued = true;
            while (continued && pos < text.size()) {
                const std::string_view more = next_line();
                continued = !more.empty() && more.back() == '\\';
                joined += ' ';
                joined += continued ? more.substr(0, more.size() - 1) : more;
            }
            line = joined;
        }
        parser.parse_line(line, first_line);
    }
    return parser.finish();
}

}  // namespace beamtrace
