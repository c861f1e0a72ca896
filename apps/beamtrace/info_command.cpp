// `beamtrace info FILE.las [--stats] [--json]`: a human-readable summary of a LAS file's header,
// VLRs and CRS; with --stats the statistics of its points (io/las_stats.hpp); --json for scripts.
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_crs.hpp"
#include "beamtrace/io/las_extra_bytes.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/las_stats.hpp"
#include "commands.hpp"
#include "progress_bar.hpp"

namespace beamtrace::cli {
namespace {

struct InfoOptions {
    std::string file;
    std::size_t points = 0;
    bool stats = false;
    bool json = false;
};

/// The shortest text that reads back as `v`, without an exponent for everyday magnitudes.
template <typename T>
std::string shortest(T v) {
    char buf[64];
    v = v == T(0) ? T(0) : v;  // -0 reads 0
    const T a = v < 0 ? -v : v;
    const bool fixed = a == 0 || (a >= T(1e-9) && a < T(1e15));
    const auto [end, ec] = fixed ? std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed)
                                 : std::to_chars(buf, buf + sizeof buf, v);
    return ec == std::errc() ? std::string(buf, end) : std::string("?");
}

std::string triple(const Vec3d& v) {
    return shortest(v.x) + " " + shortest(v.y) + " " + shortest(v.z);
}

/// `v` with the decimals of the coordinate step `step` (0.01: two) where it is that close to
/// such a number (848935.2000000001 as 848935.20), else the shortest text.
std::string at_step(double v, double step) {
    for (int d = 0; d <= 9 && std::isfinite(v) && step > 0; ++d) {
        const double steps = step * std::pow(10.0, d);
        if (std::abs(steps - std::round(steps)) <= 1e-6 * steps) {
            const double tens = std::pow(10.0, d);
            if (std::abs(v - std::round(v * tens) / tens) > 1e-6 * step) {
                break;
            }
            char buf[64];
            const double at = std::round(v * tens) / tens;
            std::snprintf(buf, sizeof buf, "%.*f", d, at == 0 ? 0.0 : at);  // -0.00 reads 0.00
            return buf;
        }
    }
    return shortest(v);
}

std::string triple(const Vec3d& v, const Vec3d& step) {
    return at_step(v.x, step.x) + " " + at_step(v.y, step.y) + " " + at_step(v.z, step.z);
}

void print_point(std::size_t index, const LasPoint& p, const LasHeader& h) {
    std::printf("  #%zu: xyz %s, intensity %u, return %u of %u, class %u%s%s%s%s", index,
                triple({p.x, p.y, p.z}, h.scale).c_str(), p.intensity, p.return_number,
                p.number_of_returns, p.classification, p.synthetic ? " synthetic" : "",
                p.key_point ? " key-point" : "", p.withheld ? " withheld" : "",
                p.overlap ? " overlap" : "");
    std::printf(", scan angle %s deg, source %u", shortest(p.scan_angle_deg).c_str(),
                p.point_source_id);
    if (las_format_has_gps_time(h.point_format)) {
        std::printf(", gps time %s", shortest(p.gps_time).c_str());
    }
    if (las_format_has_rgb(h.point_format)) {
        std::printf(", rgb %u %u %u", p.red, p.green, p.blue);
    }
    if (las_format_has_nir(h.point_format)) {
        std::printf(", nir %u", p.nir);
    }
    std::printf("\n");
}

void print_header(const std::string& file, const LasHeader& h) {
    std::printf("file:                %s\n", file.c_str());
    std::printf("LAS version:         %d.%d\n", h.version_major, h.version_minor);
    std::printf("point format:        %d (record length %u bytes, %zu extra)\n", h.point_format,
                h.point_record_length, h.extra_bytes_per_point());
    std::printf("point count:         %llu\n", static_cast<unsigned long long>(h.point_count));
    if (h.version_minor >= 4) {
        std::printf("legacy point count:  %u\n", h.legacy_point_count);
    }
    const std::size_t returns = h.version_minor >= 4 ? 15 : 5;
    std::string by_return;
    for (std::size_t i = 0; i < returns; ++i) {
        by_return += (i ? " " : "") + std::to_string(h.points_by_return[i]);
    }
    std::printf("points by return:    %s\n", by_return.c_str());
    std::printf("scale:               %s\n", triple(h.scale).c_str());
    std::printf("offset:              %s\n", triple(h.offset).c_str());
    std::printf("min:                 %s\n", triple(h.min, h.scale).c_str());
    std::printf("max:                 %s\n", triple(h.max, h.scale).c_str());
    std::printf("global encoding:     0x%04x (GPS time: %s%s)\n", h.global_encoding,
                h.gps_time_is_standard() ? "adjusted standard GPS time" : "GPS week time",
                h.crs_is_wkt() ? ", CRS: WKT" : "");
    std::printf("system identifier:   \"%s\"\n", h.system_identifier.c_str());
    std::printf("generating software: \"%s\"\n", h.generating_software.c_str());
    std::printf("created:             day %u of %u\n", h.creation_day_of_year, h.creation_year);
    std::printf("file source id:      %u\n", h.file_source_id);
    std::printf("header size:         %u bytes; point data at byte %u\n", h.header_size,
                h.offset_to_point_data);
}

/// One line per descriptor of an Extra Bytes VLR (nothing for one that does not parse).
void print_extra_bytes(const LasVlr& v) {
    static constexpr std::array<const char*, 11> kTypes = {"bytes", "uint8",   "int8",   "uint16",
                                                           "int16", "uint32",  "int32",  "uint64",
                                                           "int64", "float32", "float64"};
    std::vector<LasExtraBytesDescriptor> fields;
    try {
        fields = las_extra_bytes_descriptors(std::span(&v, 1));
    } catch (const InputError&) {
        return;
    }
    for (const LasExtraBytesDescriptor& e : fields) {
        const auto t = static_cast<std::size_t>(e.data_type);
        std::string line = "    " + e.name + ": " + (t < kTypes.size() ? kTypes[t] : "?");
        if ((e.options & LasExtraBytesDescriptor::kScale) != 0) {
            line += " x " + shortest(e.scale);
        }
        if ((e.options & LasExtraBytesDescriptor::kNoData) != 0) {
            line += ", no data " + shortest(e.no_data);
        }
        std::printf("%s  \"%s\"\n", line.c_str(), e.description.c_str());
    }
}

void print_vlrs(const LasReader& reader) {
    const LasHeader& h = reader.header();
    std::size_t n_vlr = 0;
    for (const auto& v : reader.vlrs()) {
        n_vlr += v.extended ? 0 : 1;
    }
    std::printf("VLRs:                %zu\n", n_vlr);
    for (const auto& v : reader.vlrs()) {
        if (v.extended && &v == &reader.vlrs()[n_vlr]) {
            std::printf("EVLRs:               %u (from byte %llu)\n", h.number_of_evlrs,
                        static_cast<unsigned long long>(h.start_of_first_evlr));
        }
        std::printf("  %-16s %5u  %8llu bytes  \"%s\"\n", v.user_id.c_str(), v.record_id,
                    static_cast<unsigned long long>(v.length), v.description.c_str());
        if (v.user_id == "LASF_Spec" && v.record_id == 4) {
            print_extra_bytes(v);
        }
    }
}

void print_crs(const LasFileCrs& c) {
    const char* from = c.source == LasCrsSource::wkt       ? "the OGC WKT record"
                       : c.source == LasCrsSource::geotiff ? "the GeoTIFF keys"
                                                           : "";
    if (c.crs.empty()) {
        std::printf("CRS:                 none%s%s\n", *from ? " readable from " : "", from);
    } else {
        std::printf("CRS:                 %s, from %s\n", describe_crs(c.crs).c_str(), from);
    }
    if (!c.citation.empty()) {
        std::printf("  citation: \"%s\"\n", c.citation.c_str());
    }
    if (c.vertical_epsg != 0) {
        std::printf("  vertical: EPSG:%u\n", c.vertical_epsg);
    }
    for (const std::string& w : c.warnings) {
        std::printf("  warning: %s\n", w.c_str());
    }
}

template <std::size_t N>
std::string counts(const std::array<std::uint64_t, N>& by_value) {
    std::string text;
    for (std::size_t v = 0; v < N; ++v) {
        if (by_value[v] != 0) {
            text +=
                (text.empty() ? "" : ", ") + std::to_string(v) + ": " + std::to_string(by_value[v]);
        }
    }
    return text.empty() ? "-" : text;
}

/// min and max at the values' step (a coordinate's scale, 1 for integers; 0: shortest), the
/// mean with `mean_decimals` decimals.
void print_field(const char* name, const LasFieldStats& f, double step, int mean_decimals) {
    const auto value = [&](double v) { return step > 0 ? at_step(v, step) : shortest(v); };
    char mean[64];
    std::snprintf(mean, sizeof mean, "%.*f", mean_decimals, f.mean);
    std::printf("  %-18s min %s  max %s  mean %s\n", name, value(f.min).c_str(),
                value(f.max).c_str(), mean);
}

/// Decimals of a coordinate step (0.001: 3), at most 9.
int decimals_of(double step) {
    int d = 0;
    while (d < 9 && std::abs(step * std::pow(10.0, d) - std::round(step * std::pow(10.0, d))) >
                        1e-6 * step * std::pow(10.0, d)) {
        ++d;
    }
    return d;
}

void print_stats(const LasStats& s, const Vec3d& scale) {
    std::printf("statistics:          %llu points read\n",
                static_cast<unsigned long long>(s.points));
    if (s.points > 0) {
        print_field("x:", s.x, scale.x, decimals_of(scale.x) + 1);
        print_field("y:", s.y, scale.y, decimals_of(scale.y) + 1);
        print_field("z:", s.z, scale.z, decimals_of(scale.z) + 1);
        print_field("intensity:", s.intensity, 1.0, 1);
        if (s.gps_time) {
            print_field("gps time:", *s.gps_time, 0.0, 6);
        }
    }
    std::printf("  %-18s %s\n", "classification:", counts(s.by_classification).c_str());
    std::printf("  %-18s %s\n", "return number:", counts(s.by_return_number).c_str());
    std::printf("  %-18s %s\n", "number of returns:", counts(s.by_number_of_returns).c_str());
    if (s.density_per_area) {
        std::printf(
            "  %-18s %.6g points per square unit over the x-y bounding box (%.6g square "
            "units)\n",
            "density:", *s.density_per_area, s.footprint_area);
    } else {
        std::printf("  %-18s undefined (the x-y bounding box has no area)\n", "density:");
    }
}

/// The points' statistics, with a progress bar on a terminal.
LasStats read_stats(LasReader& reader) {
    ProgressBar bar("reading points", stderr_is_terminal());
    LasStats s = compute_las_stats(
        reader, [&](std::size_t done, std::size_t total) { bar.update(done, total); });
    bar.finish();
    return s;
}

int run(const InfoOptions& o) {
    LasReader reader(o.file);
    const LasHeader& h = reader.header();
    const LasFileCrs crs = las_file_crs(h, reader.vlrs());
    std::optional<LasStats> stats;
    if (o.stats) {
        stats = read_stats(reader);
        reader.seek(0);
    }
    if (o.json) {
        std::printf(
            "%s\n",
            las_info_json(o.file, h, reader.vlrs(), crs, stats ? &*stats : nullptr).c_str());
        return 0;
    }
    print_header(o.file, h);
    print_vlrs(reader);
    print_crs(crs);
    if (stats) {
        print_stats(*stats, h.scale);
    }
    if (o.points > 0) {
        std::vector<LasPoint> points(o.points);
        const std::size_t n = reader.read(points);
        std::printf("first %zu point(s):\n", n);
        for (std::size_t i = 0; i < n; ++i) {
            print_point(i, points[i], h);
        }
    }
    return 0;
}

}  // namespace

std::function<int()> add_info_command(CLI::App& app) {
    auto opts = std::make_shared<InfoOptions>();
    CLI::App* cmd = app.add_subcommand("info",
                                       "Print the header, VLRs, EVLRs and CRS of a LAS or LAZ file "
                                       "(LAS 1.0-1.4); --stats, --json");
    cmd->add_option("file", opts->file, "LAS or LAZ file")->required();
    cmd->add_option("--points", opts->points, "Also print the first N points")
        ->capture_default_str();
    cmd->add_flag("--stats", opts->stats,
                  "Read every point: counts by class and return, min/max/mean of x, y, z, "
                  "intensity and GPS time, density");
    cmd->add_flag("--json", opts->json, "Print one JSON object (with --stats: and the statistics)");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
