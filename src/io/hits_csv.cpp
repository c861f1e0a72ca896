#include "beamtrace/io/hits_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <string>
#include <string_view>
#include <system_error>

#include "beamtrace/core/error.hpp"
#include "text/file_bytes.hpp"
#include "text/row_writer.hpp"

namespace beamtrace {

namespace {

constexpr std::string_view kHeader = kHitsCsvHeader.substr(0, kHitsCsvHeader.size() - 1);
constexpr std::size_t kMaxRowBytes = 64;  // 20 + 1 + 15 + 1 + 10 + 1 at most

/// Parses all of `field` as a number of type T.
template <typename T>
bool parse_field(std::string_view field, T& value) {
    const char* end = field.data() + field.size();
    const auto [ptr, ec] = std::from_chars(field.data(), end, value);
    return ec == std::errc{} && ptr == end && !field.empty();
}

/// Writes the row of ray `i` at `p` (room for kMaxRowBytes); returns its end.
char* put_row(const HitBatch& hits, std::size_t i, char* p, char* end) {
    p = std::to_chars(p, end, i).ptr;
    *p++ = ',';
    if (hits.hit(i)) {
        p = std::to_chars(p, end, hits.t[i]).ptr;
        *p++ = ',';
        p = std::to_chars(p, end, hits.face[i]).ptr;
        *p++ = '\n';
    } else {
        constexpr std::string_view kMiss = "inf,-1\n";
        std::memcpy(p, kMiss.data(), kMiss.size());
        p += kMiss.size();
    }
    return p;
}

}  // namespace

void append_hits_csv_rows(const HitBatch& hits, std::size_t begin, std::size_t end,
                          std::string& out) {
    const std::size_t start = out.size();
    out.resize(start + (end - begin) * kMaxRowBytes);
    char* p = out.data() + start;
    char* const limit = out.data() + out.size();
    for (std::size_t i = begin; i < end; ++i) {
        p = put_row(hits, i, p, limit);
    }
    out.resize(static_cast<std::size_t>(p - out.data()));
}

void write_hits_csv(const std::filesystem::path& path, const HitBatch& hits) {
    const std::size_t n = hits.size();
    if (hits.face.size() != n) {
        throw OutputError(path.string() + ": hit batch has " + std::to_string(n) + " ranges but " +
                          std::to_string(hits.face.size()) + " face IDs");
    }
    detail::RowWriter rows(path, kHeader, kMaxRowBytes);
    char* const end = rows.end();
    for (std::size_t i = 0; i < n; ++i) {
        rows.end_row(put_row(hits, i, rows.row(), end));
    }
    rows.commit();
}

HitsCsv read_hits_csv(const std::filesystem::path& path) {
    const std::string file = path.string();
    const std::string text = detail::read_file_bytes(path);
    HitsCsv table;
    const auto lines = std::size_t(std::count(text.begin(), text.end(), '\n'));
    table.ray.reserve(lines);
    table.range_m.reserve(lines);
    table.face_id.reserve(lines);
    std::size_t pos = 0;
    long line_no = 0;
    bool seen_header = false;
    while (pos < text.size()) {
        std::size_t eol = text.find('\n', pos);
        if (eol == std::string::npos) {
            eol = text.size();
        }
        std::string_view line(text.data() + pos, eol - pos);
        pos = eol + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') {
            line.remove_suffix(1);
        }
        if (!seen_header) {
            if (line != kHeader) {
                throw InputError(file, line_no,
                                 "expected the header '" + std::string(kHeader) + "'");
            }
            seen_header = true;
            continue;
        }
        if (line.empty()) {
            continue;
        }
        const std::size_t c1 = line.find(',');
        const std::size_t c2 = c1 == std::string_view::npos ? c1 : line.find(',', c1 + 1);
        if (c2 == std::string_view::npos || line.find(',', c2 + 1) != std::string_view::npos) {
            throw InputError(file, line_no, "expected 3 fields: ray,range_m,face_id");
        }
        std::uint64_t ray = 0;
        double range = 0.0;
        std::int64_t face = 0;
        if (!parse_field(line.substr(0, c1), ray)) {
            throw InputError(file, line_no, "malformed ray index");
        }
        if (!parse_field(line.substr(c1 + 1, c2 - c1 - 1), range)) {
            throw InputError(file, line_no, "malformed range");
        }
        if (!parse_field(line.substr(c2 + 1), face)) {
            throw InputError(file, line_no, "malformed face ID");
        }
        table.ray.push_back(ray);
        table.range_m.push_back(range);
        table.face_id.push_back(face);
    }
    if (!seen_header) {
        throw InputError(file, "empty file (expected the header '" + std::string(kHeader) + "')");
    }
    return table;
}

}  // namespace beamtrace
