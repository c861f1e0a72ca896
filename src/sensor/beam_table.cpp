#include "beamtrace/sensor/beam_table.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "text/file_bytes.hpp"
#include "text/quote.hpp"
#include "text/text_scan.hpp"

namespace beamtrace {
namespace {

enum class Column { elevation, azimuth, time, channel };
constexpr std::array<std::string_view, 4> kColumnNames{"elevation_deg", "azimuth_offset_deg",
                                                       "time_offset_s", "channel"};

std::string_view trim(std::string_view s) {
    while (!s.empty() && detail::is_blank(s.front())) {
        s.remove_prefix(1);
    }
    while (!s.empty() && detail::is_blank(s.back())) {
        s.remove_suffix(1);
    }
    return s;
}

/// The comma-separated fields of a line, trimmed.
std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> out;
    while (true) {
        const std::size_t comma = line.find(',');
        out.push_back(trim(line.substr(0, comma)));
        if (comma == std::string_view::npos) {
            return out;
        }
        line.remove_prefix(comma + 1);
    }
}

/// Reads one table: the header's columns, then the rows.
class TableReader {
  public:
    TableReader(std::string path, RotatingScannerConfig& config)
        : path_(std::move(path)), config_(config) {}

    void header(std::string_view line, long number) {
        for (const std::string_view name : split(line)) {
            std::optional<Column> column;
            for (std::size_t k = 0; k < kColumnNames.size(); ++k) {
                if (name == kColumnNames[k]) {
                    column = static_cast<Column>(k);
                }
            }
            if (!column) {
                fail(number, "unknown column " + detail::quote_value(name) +
                                 " in the header (expected elevation_deg, azimuth_offset_deg, "
                                 "time_offset_s, channel)");
            }
            for (const Column seen : columns_) {
                if (seen == *column) {
                    fail(number, "column " + std::string(name) + " named twice in the header");
                }
            }
            columns_.push_back(*column);
        }
        if (std::find(columns_.begin(), columns_.end(), Column::elevation) == columns_.end()) {
            fail(number, "the header must name an elevation_deg column");
        }
        config_.beam_elevations_deg.clear();
        config_.beam_azimuth_offsets_deg.clear();
        config_.beam_time_offsets_s.clear();
        config_.beam_channels.clear();
    }

    void row(std::string_view line, long number) {
        const std::vector<std::string_view> fields = split(line);
        if (fields.size() != columns_.size()) {
            fail(number, "expected " + std::to_string(columns_.size()) + " fields, got " +
                             std::to_string(fields.size()));
        }
        if (config_.beam_elevations_deg.size() == kMaxBeamTableRows) {
            fail(number, "more than " + std::to_string(kMaxBeamTableRows) +
                             " rows, the limit for a beam table");
        }
        for (std::size_t k = 0; k < fields.size(); ++k) {
            store(columns_[k], fields[k], number, k + 1);
        }
    }

    [[nodiscard]] bool has_header() const { return !columns_.empty(); }
    [[nodiscard]] std::size_t rows() const { return config_.beam_elevations_deg.size(); }
    [[noreturn]] void fail(long line, const std::string& what) const {
        throw InputError(path_, line, what);
    }

  private:
    void store(Column column, std::string_view field, long line, std::size_t index) {
        const std::string where = "column " + std::to_string(index) + " (" +
                                  std::string(kColumnNames[static_cast<std::size_t>(column)]) +
                                  "): ";
        if (column == Column::channel) {
            std::uint16_t ch = 0;
            if (!detail::parse_number(field, ch)) {
                fail(line, where + "expected a channel number 0-65535, got " +
                               detail::quote_value(field));
            }
            config_.beam_channels.push_back(ch);
            return;
        }
        double v = 0.0;
        if (!detail::parse_number(field, v) || !std::isfinite(v)) {
            fail(line, where + "expected a finite number, got " + detail::quote_value(field));
        }
        if (column == Column::elevation && !(v >= -90.0 && v <= 90.0)) {
            fail(line, where + "must be in [-90, 90] degrees");
        }
        if (column == Column::time && v < 0.0) {
            fail(line, where + "must not be negative");
        }
        (column == Column::elevation ? config_.beam_elevations_deg
         : column == Column::azimuth ? config_.beam_azimuth_offsets_deg
                                     : config_.beam_time_offsets_s)
            .push_back(v);
    }

    std::string path_;
    RotatingScannerConfig& config_;
    std::vector<Column> columns_;
};

}  // namespace

void read_beam_table_csv(const std::filesystem::path& path, RotatingScannerConfig& config) {
    const std::string text = detail::read_bounded_file(path, "beam table", kMaxBeamTableBytes);
    RotatingScannerConfig out = config;
    TableReader reader(path.string(), out);
    std::string_view rest = text;
    long number = 0;
    while (!rest.empty()) {
        const std::size_t eol = rest.find('\n');
        const std::string_view line = trim(rest.substr(0, eol));
        rest.remove_prefix(eol == std::string_view::npos ? rest.size() : eol + 1);
        ++number;
        if (line.empty() || line.front() == '#') {
            continue;
        }
        if (!reader.has_header()) {
            reader.header(line, number);
        } else {
            reader.row(line, number);
        }
    }
    if (!reader.has_header() || reader.rows() == 0) {
        throw InputError(path.string(),
                         "no beam rows (expected a header such as "
                         "'elevation_deg,azimuth_offset_deg,time_offset_s' and "
                         "one row per laser)");
    }
    config = std::move(out);
}

namespace {

void append_number(std::string& s, double v) {
    std::array<char, 32> buf{};
    const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    s.append(buf.data(), ec == std::errc() ? end : buf.data());
}

}  // namespace

void write_beam_table_csv(const std::filesystem::path& path, const RotatingScannerConfig& config) {
    const std::size_t beams = config.beam_elevations_deg.size();
    const double step_s = 1.0 / config.pulse_rate_hz();
    std::string s = "elevation_deg,azimuth_offset_deg,time_offset_s,channel\n";
    for (std::size_t b = 0; b < beams; ++b) {
        append_number(s, config.beam_elevations_deg[b]);
        s += ',';
        append_number(
            s, config.beam_azimuth_offsets_deg.empty() ? 0.0 : config.beam_azimuth_offsets_deg[b]);
        s += ',';
        append_number(s, config.beam_time_offsets_s.empty() ? static_cast<double>(b) * step_s
                                                            : config.beam_time_offsets_s[b]);
        s += ',';
        s += std::to_string(config.beam_channels.empty() ? b : config.beam_channels[b]);
        s += '\n';
    }
    std::ofstream f(path, std::ios::binary);
    f << s;
    if (!f.flush()) {
        throw InputError(path.string(), "cannot write the beam table");
    }
}

}  // namespace beamtrace
