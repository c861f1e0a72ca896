#include "beamtrace/io/las_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

namespace beamtrace {
namespace {

using Json = nlohmann::ordered_json;  // keys in the order written

/// Minimum, maximum and a compensated (Neumaier) sum of one field.
struct Accumulator {
    double min = std::numeric_limits<double>::infinity();
    double max = -std::numeric_limits<double>::infinity();
    double sum = 0.0;
    double compensation = 0.0;

    void add(double v) {
        min = std::min(min, v);
        max = std::max(max, v);
        const double t = sum + v;
        compensation += std::fabs(sum) >= std::fabs(v) ? (sum - t) + v : (v - t) + sum;
        sum = t;
    }
    [[nodiscard]] LasFieldStats result(std::uint64_t n) const {
        if (n == 0) {
            return {};
        }
        return {min, max, (sum + compensation) / static_cast<double>(n)};
    }
};

struct Accumulators {
    Accumulator x, y, z, intensity, gps_time;
};

void add_chunk(std::span<const LasPoint> points, LasStats& s, Accumulators& a) {
    for (const LasPoint& p : points) {
        ++s.by_classification[p.classification];
        ++s.by_return_number[p.return_number & 15u];
        ++s.by_number_of_returns[p.number_of_returns & 15u];
        a.x.add(p.x);
        a.y.add(p.y);
        a.z.add(p.z);
        a.intensity.add(p.intensity);
        a.gps_time.add(p.gps_time);
    }
}

[[nodiscard]] std::string crs_source_name(LasCrsSource s) {
    switch (s) {
        case LasCrsSource::wkt:
            return "wkt";
        case LasCrsSource::geotiff:
            return "geotiff";
        case LasCrsSource::none:
            break;
    }
    return "none";
}

template <std::size_t N>
[[nodiscard]] Json counts(const std::array<std::uint64_t, N>& by_value) {
    Json out = Json::object();
    for (std::size_t v = 0; v < N; ++v) {
        if (by_value[v] != 0) {
            out[std::to_string(v)] = by_value[v];
        }
    }
    return out;
}

[[nodiscard]] Json field(const LasFieldStats& f, std::uint64_t points) {
    if (points == 0) {
        return nullptr;
    }
    return {{"min", f.min}, {"max", f.max}, {"mean", f.mean}};
}

[[nodiscard]] Json triple(const Vec3d& v) {
    return Json::array({v.x, v.y, v.z});
}

[[nodiscard]] Json crs_json(const LasFileCrs& c) {
    Json out = {{"source", crs_source_name(c.source)}};
    out["epsg"] = c.crs.epsg != 0 ? Json(c.crs.epsg) : Json(nullptr);
    out["name"] = c.crs.empty() ? Json(nullptr) : Json(describe_crs(c.crs));
    out["wkt"] = c.crs.empty() ? Json(nullptr) : Json(c.crs.wkt);
    if (c.source == LasCrsSource::geotiff) {
        out["vertical_epsg"] = c.vertical_epsg != 0 ? Json(c.vertical_epsg) : Json(nullptr);
        out["citation"] = c.citation;
    }
    out["warnings"] = c.warnings;
    return out;
}

[[nodiscard]] Json stats_json(const LasStats& s) {
    Json out = {{"points", s.points},
                {"by_classification", counts(s.by_classification)},
                {"by_return_number", counts(s.by_return_number)},
                {"by_number_of_returns", counts(s.by_number_of_returns)},
                {"x", field(s.x, s.points)},
                {"y", field(s.y, s.points)},
                {"z", field(s.z, s.points)},
                {"intensity", field(s.intensity, s.points)}};
    out["gps_time"] = s.gps_time ? field(*s.gps_time, s.points) : Json(nullptr);
    out["footprint_area"] = s.footprint_area;
    out["density_per_area"] = s.density_per_area ? Json(*s.density_per_area) : Json(nullptr);
    return out;
}

}  // namespace

LasStats compute_las_stats(LasReader& reader, const ProgressFn& progress) {
    LasStats s;
    Accumulators a;
    const LasHeader& h = reader.header();
    std::vector<LasPoint> chunk(LasReader::kChunkPoints);
    while (const std::size_t n = reader.read(chunk)) {
        add_chunk(std::span<const LasPoint>(chunk).first(n), s, a);
        s.points += n;
        if (progress) {
            progress(static_cast<std::size_t>(s.points), static_cast<std::size_t>(h.point_count));
        }
    }
    s.x = a.x.result(s.points);
    s.y = a.y.result(s.points);
    s.z = a.z.result(s.points);
    s.intensity = a.intensity.result(s.points);
    if (las_format_has_gps_time(h.point_format)) {
        s.gps_time = a.gps_time.result(s.points);
    }
    s.footprint_area = (s.x.max - s.x.min) * (s.y.max - s.y.min);
    if (s.footprint_area > 0.0) {
        s.density_per_area = static_cast<double>(s.points) / s.footprint_area;
    }
    s.crs = las_file_crs(h, reader.vlrs());
    return s;
}

std::string las_info_json(const std::filesystem::path& path, const LasHeader& h,
                          std::span<const LasVlr> vlrs, const LasFileCrs& crs,
                          const LasStats* stats, int indent) {
    Json out = {
        {"file", path.string()},
        {"las_version", std::to_string(h.version_major) + "." + std::to_string(h.version_minor)},
        {"point_format", h.point_format},
        {"point_record_length", h.point_record_length},
        {"point_count", h.point_count},
        {"points_by_return", h.points_by_return},
        {"scale", triple(h.scale)},
        {"offset", triple(h.offset)},
        {"min", triple(h.min)},
        {"max", triple(h.max)},
        {"global_encoding", h.global_encoding},
        {"system_identifier", h.system_identifier},
        {"generating_software", h.generating_software},
    };
    Json records = Json::array();
    for (const LasVlr& v : vlrs) {
        records.push_back({{"user_id", v.user_id},
                           {"record_id", v.record_id},
                           {"bytes", v.length},
                           {"description", v.description},
                           {"extended", v.extended}});
    }
    out["vlrs"] = std::move(records);
    out["crs"] = crs_json(crs);
    if (stats != nullptr) {
        out["stats"] = stats_json(*stats);
    }
    return out.dump(indent, ' ', false, Json::error_handler_t::replace);
}

}  // namespace beamtrace
