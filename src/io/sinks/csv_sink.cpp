// points.csv: one row per point (x,y,z,gps_time,range_m,classification,point_source_id,beam,
// scan_angle_deg and, with physics, intensity,return_number,number_of_returns), streamed.
// Numbers read like the LAS file's: coordinates and ranges at the LAS scale's decimals, times
// as the LAS file holds them, scan angles in the LAS format's 0.006 degree steps, trailing zeros
// dropped, no "-0". output.extra_bytes adds a column per attribute, named as in LAS, except
// range_m and beam, columns already: incidence_angle_deg and echo_width_ns at the LAS scale's
// 2 decimals (an unknown echo width is an empty field), object_id (extra_columns.hpp). A survey
// with `scanners:` adds a last column, scanner_channel (the LAS scanner channel, 0-3).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "beamtrace/io/las_writer.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "io/sinks/byte_file_sink.hpp"
#include "io/sinks/extra_columns.hpp"

namespace beamtrace {

namespace {

/// Longest CSV row: 6 fixed numbers of at most 309 digits, a point and 9 decimals each (any
/// finite double), 3 + 3 integers.
constexpr std::size_t kMaxCsvRow = 2048;

/// How each column kind is written.
struct CsvDecimals {
    Vec3d scale{0.001, 0.001, 0.001}, offset;  ///< the LAS file's: x, y, z are its values
    int xyz = 3;                               ///< decimals of the scale (0.001 m: 3)
    int angle = 3;                             ///< 0.001 degree
};

/// The fewest decimals that write `step` exactly (0.001: 3, 0.0025: 4).
int decimals_of(double step) {
    for (int d = 0; d < 12; ++d) {
        const double scaled = step * std::pow(10.0, d);
        if (std::abs(scaled - std::round(scaled)) < 1e-9 * scaled) {
            return d;
        }
    }
    return 12;
}

/// Writes `v` with at most `decimals` decimals at `c`: trailing zeros and a bare point dropped,
/// and a value that rounds to zero written "0" (never "-0").
char* put_fixed(char* c, char* end, double v, int decimals) {
    char* const start = c;
    c = std::to_chars(c, end, v, std::chars_format::fixed, decimals).ptr;
    if (decimals > 0) {
        while (c[-1] == '0') {
            --c;
        }
        if (c[-1] == '.') {
            --c;
        }
    }
    if (c - start == 2 && start[0] == '-' && start[1] == '0') {
        start[0] = '0';
        c = start + 1;
    }
    return c;
}

/// The attributes of `extra` that are not columns already (range_m and beam are).
std::vector<PointAttribute> extra_csv_columns(std::span<const PointAttribute> extra) {
    std::vector<PointAttribute> out;
    for (const PointAttribute a : extra) {
        if (a != PointAttribute::range && a != PointAttribute::beam) {
            out.push_back(a);
        }
    }
    return out;
}

/// Writes `,value` of each of `extra` at `c` (measurements at 2 decimals, the LAS scale 0.01).
char* put_extra(char* c, char* end, std::span<const PointAttribute> extra, const BlockPoint& p) {
    for (const PointAttribute a : extra) {
        *c++ = ',';
        const double v = detail::extra_column_value(a, p);
        if (detail::extra_column_is_integer(a)) {
            c = std::to_chars(c, end, static_cast<std::uint32_t>(v)).ptr;
        } else if (std::isfinite(v)) {
            c = put_fixed(c, end, std::round(v * 100.0) / 100.0, 2);
        }
    }
    return c;
}

/// Appends one CSV row to `out`.
void append_csv_row(std::string& out, const BlockPoint& p, bool physics, const CsvDecimals& d,
                    std::span<const PointAttribute> extra, bool channel) {
    char row[kMaxCsvRow];
    char* c = row;
    char* const end = row + kMaxCsvRow;
    const auto num = [&](double v, int decimals) {
        c = put_fixed(c, end, v, decimals);
        *c++ = ',';
    };
    // The coordinate the LAS file holds: the nearest step of its scale from its offset (as
    // LasWriter rounds), so the two files agree to the last digit.
    const double xyz[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
        const double steps = std::round((xyz[k] - d.offset[k]) * (1.0 / d.scale[k]));
        num(std::isfinite(steps) ? steps * d.scale[k] + d.offset[k] : xyz[k], d.xyz);
    }
    // The time as the LAS file holds it (a double): its shortest round-trip form, but never
    // with an exponent (0.00000078125, not 7.8125e-07).
    c = std::to_chars(c, end, p.gps_time + 0.0, std::chars_format::fixed).ptr;
    *c++ = ',';
    c = std::to_chars(c, end, p.range_m).ptr;  // a float, as in points.pcd: shortest form
    *c++ = ',';
    for (unsigned v :
         {unsigned{p.classification}, unsigned{p.point_source_id}, unsigned{p.channel}}) {
        c = std::to_chars(c, end, v).ptr;
        *c++ = ',';
    }
    // The scan angle as the LAS file holds it: whole steps of 0.006 degree.
    const double angle =
        std::round(static_cast<double>(p.scan_angle_deg) * (1.0 / kScanAngleStepDeg));
    c = put_fixed(c, end, angle * kScanAngleStepDeg, d.angle);
    if (physics) {
        for (unsigned v :
             {unsigned{p.intensity}, unsigned{p.return_number}, unsigned{p.number_of_returns}}) {
            *c++ = ',';
            c = std::to_chars(c, end, v).ptr;
        }
    }
    c = put_extra(c, end, extra, p);
    if (channel) {
        *c++ = ',';
        c = std::to_chars(c, end, unsigned{p.scanner_channel}).ptr;
    }
    *c++ = '\n';
    out.append(row, static_cast<std::size_t>(c - row));
}

class CsvSink final : public detail::ByteFileSink {
  public:
    explicit CsvSink(const SinkFacts& facts)
        : ByteFileSink(facts.output_dir / "points.csv"),
          physics_(facts.physics),
          extra_(extra_csv_columns(facts.extra_bytes)),
          channel_(facts.scanners > 0) {
        // The LAS sink's scale and offset (0.001 m, or coarser for a huge extent).
        const LasWriterConfig las = las_config_for_extent(facts.lo_m, facts.hi_m, 0.001);
        decimals_.scale = las.scale;
        decimals_.offset = las.offset;
        decimals_.xyz = std::max(
            {decimals_of(las.scale.x), decimals_of(las.scale.y), decimals_of(las.scale.z)});
        std::string header =
            std::string(
                "x,y,z,gps_time,range_m,classification,point_source_id,beam,scan_angle_deg") +
            (physics_ ? ",intensity,return_number,number_of_returns" : "");
        for (const PointAttribute a : extra_) {
            header += "," + detail::extra_column_name(a);
        }
        file().write(header + (channel_ ? ",scanner_channel\n" : "\n"));
    }
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        std::string& bytes = static_cast<ByteBuffer&>(out).bytes;
        for (const BlockPoint& p : block.points) {
            append_csv_row(bytes, p, physics_, decimals_, extra_, channel_);
        }
    }

  private:
    bool physics_;
    std::vector<PointAttribute> extra_;
    bool channel_;  ///< the scanner_channel column (a survey with `scanners:`)
    CsvDecimals decimals_;
};

}  // namespace

std::unique_ptr<PointSink> make_csv_sink(const SinkFacts& facts) {
    return std::make_unique<CsvSink>(facts);
}

}  // namespace beamtrace
