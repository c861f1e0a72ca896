#include "beamtrace/sensor/rays_file.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "sensor/detail/scan_pattern_types.hpp"
#include "text/quote.hpp"
#include "text/row_writer.hpp"

namespace beamtrace {

namespace {

constexpr std::size_t kFields = 6;
constexpr std::string_view kHeader = "ox,oy,oz,dx,dy,dz";
/// Read chunk: large enough for fast reads, small enough that a tiny file costs little.
constexpr std::size_t kChunkBytes = std::size_t{64} << 10;
/// The longest line a rays file may have (docs/formats.md), to which the read buffer may grow.
constexpr std::size_t kMaxLineBytes = std::size_t{16} << 20;
constexpr std::size_t kMaxRowBytes =
    std::size_t{6} * 25;  // shortest doubles are at most 24 characters

/// Reads a file line by line through one reused buffer, so that memory stays small however
/// large the file is. Lines exclude the '\n'; one longer than kMaxLineBytes is an error, so
/// that a file without line ends (/dev/zero) is refused with little memory.
class LineReader {
  public:
    explicit LineReader(const std::filesystem::path& path)
        : path_(path.string()), file_(std::fopen(path.c_str(), "rb")), buffer_(kChunkBytes) {
        if (file_ == nullptr) {
            throw InputError(path_, std::string("cannot open: ") + std::strerror(errno));
        }
    }
    ~LineReader() { std::fclose(file_); }
    LineReader(const LineReader&) = delete;
    LineReader& operator=(const LineReader&) = delete;

    /// The next line (valid until the next call), or nothing at the end of the file.
    [[nodiscard]] std::optional<std::string_view> next() {
        while (true) {
            const char* start = buffer_.data() + begin_;
            const std::size_t available = end_ - begin_;
            if (const void* eol = std::memchr(start, '\n', available); eol != nullptr) {
                const auto length = std::size_t(static_cast<const char*>(eol) - start);
                begin_ += length + 1;
                ++line_;
                return std::string_view(start, length);
            }
            if (at_eof_) {
                if (available == 0) {
                    return std::nullopt;
                }
                begin_ = end_;
                ++line_;
                return std::string_view(start, available);  // last line without '\n'
            }
            refill();
        }
    }
    [[nodiscard]] long line_number() const { return line_; }

  private:
    void refill() {
        std::memmove(buffer_.data(), buffer_.data() + begin_, end_ - begin_);
        end_ -= begin_;
        begin_ = 0;
        if (end_ == buffer_.size()) {  // a line longer than the buffer
            if (buffer_.size() >= kMaxLineBytes) {
                throw InputError(path_, line_ + 1,
                                 "line longer than " + std::to_string(kMaxLineBytes >> 20) +
                                     " MiB, the limit for a line of a rays file");
            }
            buffer_.resize(2 * buffer_.size());
        }
        const std::size_t wanted = buffer_.size() - end_;
        const std::size_t got = std::fread(buffer_.data() + end_, 1, wanted, file_);
        end_ += got;
        if (got < wanted) {
            if (std::ferror(file_) != 0) {
                throw InputError(path_, std::string("read error: ") + std::strerror(errno));
            }
            at_eof_ = true;
        }
    }

    std::string path_;
    std::FILE* file_;
    std::vector<char> buffer_;
    std::size_t begin_ = 0;  ///< start of the unread data in buffer_
    std::size_t end_ = 0;    ///< end of the valid data in buffer_
    bool at_eof_ = false;
    long line_ = 0;
};

/// The shortest line that can hold a ray: "0,0,0,0,0,1".
constexpr std::size_t kMinRowBytes = 11;

/// Counts the lines of a regular file long enough to hold a ray (an upper bound on its rays)
/// so that the batch is allocated once, and a file of empty lines allocates nothing; 0 when
/// that is not possible — the real read then reports any error.
std::size_t count_lines(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        return 0;
    }
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (file == nullptr) {
        return 0;
    }
    std::vector<char> buffer(kChunkBytes);
    std::size_t lines = 0;
    std::size_t length = 0;  // of the line being read
    std::size_t got = 0;
    while ((got = std::fread(buffer.data(), 1, buffer.size(), file)) > 0) {
        const char* p = buffer.data();
        const char* const end = p + got;
        while (const void* eol = std::memchr(p, '\n', std::size_t(end - p))) {
            length += std::size_t(static_cast<const char*>(eol) - p);
            lines += length >= kMinRowBytes ? 1 : 0;
            length = 0;
            p = static_cast<const char*>(eol) + 1;
        }
        length += std::size_t(end - p);
    }
    std::fclose(file);
    return lines + (length >= kMinRowBytes ? 1 : 0);
}

[[nodiscard]] bool is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\r';
}

[[nodiscard]] std::string_view trim(std::string_view s) {
    while (!s.empty() && is_blank(s.front())) {
        s.remove_prefix(1);
    }
    while (!s.empty() && is_blank(s.back())) {
        s.remove_suffix(1);
    }
    return s;
}

/// Parses a whole (trimmed) field; accepts a leading '+', which from_chars does not.
[[nodiscard]] bool parse_double(std::string_view field, double& value, std::errc& error) {
    if (field.size() > 1 && field.front() == '+' && field[1] != '-' && field[1] != '+') {
        field.remove_prefix(1);
    }
    const char* end = field.data() + field.size();
    const auto [ptr, ec] = std::from_chars(field.data(), end, value);
    error = ec;
    return ec == std::errc{} && ptr == end && !field.empty();
}

/// True when the field starts like a number (so a line holding it is not a header).
[[nodiscard]] bool starts_numeric(std::string_view field) {
    if (!field.empty() && field.front() == '+') {
        field.remove_prefix(1);
    }
    double ignored = 0.0;
    const auto result = std::from_chars(field.data(), field.data() + field.size(), ignored);
    return result.ec != std::errc::invalid_argument;
}

/// Splits a line at commas into trimmed fields; returns the field count (which may exceed
/// kFields, in which case only the first kFields are stored).
std::size_t split_fields(std::string_view line, std::array<std::string_view, kFields>& fields) {
    std::size_t count = 0;
    while (true) {
        const std::size_t comma = line.find(',');
        if (count < kFields) {
            fields[count] = trim(line.substr(0, comma));
        }
        ++count;
        if (comma == std::string_view::npos) {
            return count;
        }
        line.remove_prefix(comma + 1);
    }
}

/// Scales d to unit length. Keeps it unchanged when it is unit already (to 16 ulps), so that
/// written and re-read directions stay bit-exact. Returns false for a zero-length direction.
[[nodiscard]] bool normalise(std::array<double, 3>& d) {
    constexpr double kUnitTolerance = 16.0 * std::numeric_limits<double>::epsilon();
    const double len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (std::abs(len2 - 1.0) <= kUnitTolerance) {
        return true;
    }
    // Scale by the largest component first so that tiny or huge vectors neither underflow
    // nor overflow.
    const double scale = std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])});
    if (scale == 0.0) {
        return false;
    }
    const std::array<double, 3> s = {d[0] / scale, d[1] / scale, d[2] / scale};
    const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int k = 0; k < 3; ++k) {
        d[k] = s[k] / len;
    }
    return true;
}

}  // namespace

RayBatch read_rays_csv(const std::filesystem::path& path) {
    const std::string file = path.string();
    RayBatch rays;
    rays.reserve(count_lines(path));
    LineReader reader(path);
    std::array<std::string_view, kFields> fields;
    bool first_content_line = true;
    while (const std::optional<std::string_view> raw = reader.next()) {
        const std::string_view line = trim(*raw);
        if (line.empty() || line.front() == '#') {
            continue;
        }
        const long line_no = reader.line_number();
        const std::size_t count = split_fields(line, fields);
        if (first_content_line) {
            first_content_line = false;
            bool any_numeric = false;
            for (std::size_t k = 0; k < std::min(count, kFields); ++k) {
                any_numeric = any_numeric || starts_numeric(fields[k]);
            }
            if (!any_numeric) {
                continue;  // header
            }
        }
        if (count != kFields) {
            throw InputError(file, line_no,
                             "expected 6 comma-separated values ox,oy,oz,dx,dy,dz, found " +
                                 std::to_string(count));
        }
        std::array<double, kFields> v{};
        for (std::size_t k = 0; k < kFields; ++k) {
            std::errc error{};
            if (!parse_double(fields[k], v[k], error)) {
                throw InputError(
                    file, line_no,
                    std::string(error == std::errc::result_out_of_range ? "number out of range"
                                                                        : "malformed number") +
                        " " + detail::quote_value(fields[k]) + " in field " +
                        std::to_string(k + 1) + " (" + std::string(kHeader.substr(3 * k, 2)) + ")");
            }
            if (!std::isfinite(v[k])) {
                throw InputError(file, line_no,
                                 "non-finite value " + detail::quote_value(fields[k]) +
                                     " in field " + std::to_string(k + 1) + " (" +
                                     std::string(kHeader.substr(3 * k, 2)) + ")");
            }
        }
        std::array<double, 3> d = {v[3], v[4], v[5]};
        if (!normalise(d)) {
            throw InputError(file, line_no, "zero-length direction");
        }
        rays.push_back({v[0], v[1], v[2]}, {d[0], d[1], d[2]});
    }
    if (rays.empty()) {
        throw InputError(file, "no rays found (expected lines ox,oy,oz,dx,dy,dz)");
    }
    return rays;
}

void write_rays_csv(const std::filesystem::path& path, const RayBatch& rays) {
    const std::size_t n = rays.size();
    const std::array<const std::vector<double>*, kFields> columns = {&rays.ox, &rays.oy, &rays.oz,
                                                                     &rays.dx, &rays.dy, &rays.dz};
    for (const auto* column : columns) {
        if (column->size() != n) {
            throw OutputError(path.string() + ": malformed ray batch (columns of different sizes)");
        }
    }
    detail::RowWriter rows(path, kHeader, kMaxRowBytes);
    char* const end = rows.end();
    for (std::size_t i = 0; i < n; ++i) {
        char* p = rows.row();
        for (std::size_t k = 0; k < kFields; ++k) {
            const double value = (*columns[k])[i];
            if (!std::isfinite(value)) {
                throw OutputError(path.string() + ": ray " + std::to_string(i) +
                                  " has a non-finite " + std::string(kHeader.substr(3 * k, 2)));
            }
            p = std::to_chars(p, end, value).ptr;
            *p++ = k + 1 < kFields ? ',' : '\n';
        }
        rows.end_row(p);
    }
    rows.commit();
}

ScanPatternEntry detail::rays_file_entry() {
    ScanPatternEntry e{"rays", "the rays of a CSV file (ox,oy,oz,dx,dy,dz per line)", {}};
    e.static_rays = [](const StaticScanInput& in) {
        return StaticRays{read_rays_csv(in.rays_file), std::nullopt};
    };
    e.reads_rays_file = true;
    return e;
}

}  // namespace beamtrace
