// ESRI ASCII grids, the raster loader dispatch, and raster height fields as triangle meshes.
#include "beamtrace/scene/raster_terrain.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>

#include "beamtrace/core/error.hpp"
#include "text/file_bytes.hpp"
#include "text/text_scan.hpp"

namespace beamtrace {
namespace {

/// The header of an ESRI ASCII grid, as far as it has been read.
struct AsciiHeader {
    std::optional<int> ncols, nrows;
    std::optional<double> xllcorner, xllcenter, yllcorner, yllcenter, cellsize, dx, dy;
    std::optional<float> nodata;
};

[[nodiscard]] bool is_space(char c) {
    return c == '\n' || detail::is_blank(c);
}

[[nodiscard]] long line_at(std::string_view text, std::size_t pos) {
    long line = 1;
    for (std::size_t i = 0; i < pos && i < text.size(); ++i) {
        line += text[i] == '\n' ? 1 : 0;
    }
    return line;
}

/// Stores `value` (the token after `key` on line `line`) in the header field named by `key`.
void set_header_value(AsciiHeader& h, std::string_view key, std::string_view value,
                      const std::string& path, long line) {
    const std::string name(key);
    auto set_int = [&](std::optional<int>& field) {
        int v = 0;
        if (!detail::parse_number(value, v) || v <= 0) {
            throw InputError(
                path, line,
                "'" + name + "' must be a positive integer, got '" + std::string(value) + "'");
        }
        field = v;
    };
    auto set_double = [&](std::optional<double>& field) {
        double v = 0;
        if (!detail::parse_number(value, v) || !std::isfinite(v)) {
            throw InputError(path, line,
                             "'" + name + "' must be a number, got '" + std::string(value) + "'");
        }
        field = v;
    };
    if (detail::iequals(key, "ncols")) {
        set_int(h.ncols);
    } else if (detail::iequals(key, "nrows")) {
        set_int(h.nrows);
    } else if (detail::iequals(key, "xllcorner")) {
        set_double(h.xllcorner);
    } else if (detail::iequals(key, "xllcenter")) {
        set_double(h.xllcenter);
    } else if (detail::iequals(key, "yllcorner")) {
        set_double(h.yllcorner);
    } else if (detail::iequals(key, "yllcenter")) {
        set_double(h.yllcenter);
    } else if (detail::iequals(key, "cellsize")) {
        set_double(h.cellsize);
    } else if (detail::iequals(key, "dx")) {
        set_double(h.dx);
    } else if (detail::iequals(key, "dy")) {
        set_double(h.dy);
    } else if (detail::iequals(key, "nodata_value")) {
        float v = 0;
        if (!detail::parse_number(value, v)) {
            throw InputError(path, line,
                             "'" + name + "' must be a number, got '" + std::string(value) + "'");
        }
        h.nodata = v;
    } else {
        throw InputError(path, line, "unknown header key '" + name + "'");
    }
}

/// Reads the header lines (each "key value") up to the first line that starts with a number;
/// returns the offset of that line.
[[nodiscard]] std::size_t read_ascii_header(std::string_view text, const std::string& path,
                                            AsciiHeader& h) {
    std::size_t pos = 0;
    long line = 1;
    while (pos < text.size()) {
        const std::size_t eol = std::min(text.find('\n', pos), text.size());
        const std::string_view content = text.substr(pos, eol - pos);
        detail::TextCursor cursor(content, line);
        const std::string_view key = cursor.next();
        if (!key.empty()) {
            const char c = key.front();
            if ((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.') {
                return pos;  // the first row of values
            }
            const std::string_view value = cursor.next();
            if (value.empty()) {
                throw InputError(path, line, "no value for header key '" + std::string(key) + "'");
            }
            if (!cursor.at_end()) {
                throw InputError(path, line,
                                 "unexpected text after the value of '" + std::string(key) + "'");
            }
            set_header_value(h, key, value, path, line);
        }
        pos = eol + 1;
        ++line;
    }
    return text.size();
}

/// Refuses, before anything is allocated, ncols x nrows = `count` cells above kMaxRasterCells or
/// more than the `data_bytes` after the header can hold (at least a byte each), so the values
/// take at most 4 bytes per byte of the file.
void check_ascii_count(std::size_t count, std::size_t data_bytes, const std::string& path,
                       long line) {
    if (count > kMaxRasterCells) {
        throw InputError(path, line,
                         "ncols x nrows = " + std::to_string(count) +
                             " cells is above the limit of " + std::to_string(kMaxRasterCells) +
                             " cells per raster");
    }
    if (count > data_bytes) {
        throw InputError(path, line,
                         "ncols x nrows = " + std::to_string(count) + " values cannot fit in the " +
                             std::to_string(data_bytes) + " bytes after the header");
    }
}

}  // namespace

Raster load_esri_ascii_grid(const std::filesystem::path& path) {
    const std::string p = path.string();
    const std::string bytes = detail::read_file_bytes(path);
    const std::string_view text(bytes);
    AsciiHeader h;
    const std::size_t data_pos = read_ascii_header(text, p, h);
    const long data_line = line_at(text, data_pos);
    auto missing = [&](const std::string& what) {
        return InputError(p, data_line, "the header has no " + what);
    };
    if (!h.ncols) {
        throw missing("'ncols'");
    }
    if (!h.nrows) {
        throw missing("'nrows'");
    }
    if (h.xllcorner.has_value() == h.xllcenter.has_value()) {
        throw InputError(p, data_line, "the header needs exactly one of 'xllcorner', 'xllcenter'");
    }
    if (h.yllcorner.has_value() == h.yllcenter.has_value()) {
        throw InputError(p, data_line, "the header needs exactly one of 'yllcorner', 'yllcenter'");
    }
    const double cell_x = h.cellsize ? *h.cellsize : h.dx.value_or(0.0);
    const double cell_y = h.cellsize ? *h.cellsize : h.dy.value_or(0.0);
    if (!(cell_x > 0.0) || !(cell_y > 0.0)) {
        throw missing("positive 'cellsize' (or 'dx' and 'dy')");
    }
    Raster r;
    r.cols = *h.ncols;
    r.rows = *h.nrows;
    r.cell_x_m = cell_x;
    r.cell_y_m = -cell_y;
    r.x0_m = h.xllcenter ? *h.xllcenter : *h.xllcorner + 0.5 * cell_x;
    const double y_bottom = h.yllcenter ? *h.yllcenter : *h.yllcorner + 0.5 * cell_y;
    r.y0_m = y_bottom + static_cast<double>(r.rows - 1) * cell_y;
    r.nodata = h.nodata;

    const std::size_t count = static_cast<std::size_t>(r.cols) * static_cast<std::size_t>(r.rows);
    check_ascii_count(count, bytes.size() - data_pos, p, data_line);
    r.z.resize(count);
    const char* const begin = bytes.data();
    const char* const end = begin + bytes.size();
    const char* cur = begin + data_pos;
    for (std::size_t i = 0; i < count; ++i) {
        while (cur < end && is_space(*cur)) {
            ++cur;
        }
        if (cur == end) {
            throw InputError(p, line_at(text, bytes.size()),
                             "expected " + std::to_string(count) + " values (" +
                                 std::to_string(r.rows) + " rows of " + std::to_string(r.cols) +
                                 "), found only " + std::to_string(i));
        }
        const auto [next, ec] = std::from_chars(cur, end, r.z[i]);
        if (ec != std::errc() || (next < end && !is_space(*next))) {
            const char* token_end = cur;
            while (token_end < end && !is_space(*token_end)) {
                ++token_end;
            }
            throw InputError(p, line_at(text, static_cast<std::size_t>(cur - begin)),
                             "value " + std::to_string(i) + " '" + std::string(cur, token_end) +
                                 "' is not a number within float range");
        }
        cur = next;
    }
    while (cur < end && is_space(*cur)) {
        ++cur;
    }
    if (cur != end) {
        throw InputError(p, line_at(text, static_cast<std::size_t>(cur - begin)),
                         "more than the " + std::to_string(count) + " values the header declares");
    }
    return r;
}

Raster load_raster(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) {
        if (c >= 'A' && c <= 'Z') {
            c = static_cast<char>(c - 'A' + 'a');
        }
    }
    if (ext == ".asc") {
        return load_esri_ascii_grid(path);
    }
    if (ext == ".tif" || ext == ".tiff") {
        return load_geotiff(path);
    }
    throw InputError(path.string(), "unknown raster format '" + path.extension().string() +
                                        "' (expected .asc, .tif or .tiff)");
}

TriangleMesh raster_to_mesh(const Raster& raster, const Vec3d& origin_m) {
    if (raster.cols <= 0 || raster.rows <= 0 ||
        raster.z.size() !=
            static_cast<std::size_t>(raster.cols) * static_cast<std::size_t>(raster.rows)) {
        throw std::invalid_argument("raster_to_mesh: " + std::to_string(raster.z.size()) +
                                    " values for " + std::to_string(raster.cols) + " x " +
                                    std::to_string(raster.rows) + " cells");
    }
    constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
    if (raster.z.size() >= kNone) {
        throw std::invalid_argument("raster_to_mesh: too many cells for 32-bit indices");
    }
    TriangleMesh mesh;
    std::vector<std::uint32_t> vertex_of(raster.z.size(), kNone);
    mesh.vertices.reserve(raster.z.size());
    for (int row = 0; row < raster.rows; ++row) {
        const double y = raster.y0_m + row * raster.cell_y_m - origin_m.y;
        for (int col = 0; col < raster.cols; ++col) {
            const float z = raster.at(col, row);
            if (!raster.valid(z)) {
                continue;
            }
            const double x = raster.x0_m + col * raster.cell_x_m - origin_m.x;
            vertex_of[static_cast<std::size_t>(row) * static_cast<std::size_t>(raster.cols) +
                      static_cast<std::size_t>(col)] =
                static_cast<std::uint32_t>(mesh.vertices.size());
            mesh.vertices.emplace_back(static_cast<float>(x), static_cast<float>(y),
                                       static_cast<float>(static_cast<double>(z) - origin_m.z));
        }
    }
    // Counter-clockwise from above for a north-up raster (x east, rows going south); the
    // winding flips when exactly one axis runs the other way.
    const bool flip = raster.cell_x_m * raster.cell_y_m > 0.0;
    mesh.faces.reserve(2 * static_cast<std::size_t>(raster.cols - 1) *
                       static_cast<std::size_t>(raster.rows - 1));
    auto emit = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (a != kNone && b != kNone && c != kNone) {
            mesh.faces.push_back(flip ? Face{a, c, b} : Face{a, b, c});
        }
    };
    const auto cols = static_cast<std::size_t>(raster.cols);
    for (std::size_t row = 0; row + 1 < static_cast<std::size_t>(raster.rows); ++row) {
        for (std::size_t col = 0; col + 1 < cols; ++col) {
            const std::uint32_t top_left = vertex_of[row * cols + col];
            const std::uint32_t top_right = vertex_of[row * cols + col + 1];
            const std::uint32_t bottom_left = vertex_of[(row + 1) * cols + col];
            const std::uint32_t bottom_right = vertex_of[(row + 1) * cols + col + 1];
            emit(bottom_left, bottom_right, top_right);
            emit(bottom_left, top_right, top_left);
        }
    }
    return mesh;
}

}  // namespace beamtrace
