#include "pipeline/detail/weather_yaml.hpp"

#include <string>

namespace beamtrace::detail {
namespace {

/// Reads `n[key]` into `out` when present; false when present and not a number.
bool number(YamlChecker& c, const YAML::Node& n, const std::string& prefix, const char* key,
            double& out) {
    double v = 0;
    if (!n[key]) {
        return true;
    }
    if (!c.number(n[key], prefix + key, v)) {
        return false;
    }
    out = v;
    return true;
}

void optional_number(YamlChecker& c, const YAML::Node& n, const std::string& prefix,
                     const char* key, std::optional<double>& out) {
    double v = 0;
    if (n[key] && c.number(n[key], prefix + key, v)) {
        out = v;
    }
}

/// weather.fog: mor_m (required), extinction_per_m, backscatter_per_m_sr.
void parse_fog(YamlChecker& c, const YAML::Node& f, WeatherConfig& out) {
    if (!f.IsMap()) {
        c.error(f, "weather.fog", "expected a map with mor_m");
        return;
    }
    c.only_keys(f, "weather.fog", {"mor_m", "extinction_per_m", "backscatter_per_m_sr"});
    FogConfig fog;
    if (!f["mor_m"]) {
        c.error(f, "weather.fog.mor_m", "missing (the meteorological optical range in metres)");
        return;
    }
    if (!number(c, f, "weather.fog.", "mor_m", fog.mor_m)) {
        return;
    }
    optional_number(c, f, "weather.fog.", "extinction_per_m", fog.extinction_per_m);
    optional_number(c, f, "weather.fog.", "backscatter_per_m_sr", fog.backscatter_per_m_sr);
    out.fog = fog;
}

/// weather.rain / weather.snow: rate_mm_h (required), particle_albedo, floor_fraction.
void parse_precipitation(YamlChecker& c, const YAML::Node& r, PrecipitationKind kind,
                         WeatherConfig& out) {
    const std::string key = "weather." + std::string(to_string(kind));
    if (!r.IsMap()) {
        c.error(r, key, "expected a map with rate_mm_h");
        return;
    }
    c.only_keys(r, key, {"rate_mm_h", "particle_albedo", "floor_fraction"});
    PrecipitationConfig p;
    p.kind = kind;
    if (!r["rate_mm_h"]) {
        c.error(r, key + ".rate_mm_h", "missing (the precipitation rate in mm/h)");
        return;
    }
    if (!number(c, r, key + ".", "rate_mm_h", p.rate_mm_h)) {
        return;
    }
    optional_number(c, r, key + ".", "particle_albedo", p.particle_albedo);
    (void)number(c, r, key + ".", "floor_fraction", p.floor_fraction);
    out.precipitation = p;
}

/// The node a validate() problem's key (`weather.fog.mor_m`) names, or its deepest existing
/// parent: the error's line.
YAML::Node node_of(const YAML::Node& weather, const std::string& key) {
    YAML::Node at = weather;
    std::size_t from = key.find('.');
    while (from != std::string::npos) {
        const std::size_t to = key.find('.', from + 1);
        const std::string part = key.substr(from + 1, to == std::string::npos ? to : to - from - 1);
        const YAML::Node next = at.IsMap() ? at[part] : YAML::Node(YAML::NodeType::Undefined);
        if (!next) {
            break;
        }
        at.reset(next);
        from = to;
    }
    return at;
}

}  // namespace

void parse_weather_block(YamlChecker& c, const YAML::Node& n, WeatherConfig& out) {
    if (!n.IsMap()) {
        c.error(n, "weather", "expected a map");
        return;
    }
    c.only_keys(n, "weather",
                {"fog", "rain", "snow", "wetness", "snow_cover", "overlap_start_m",
                 "overlap_full_m", "medium_class"});
    if (n["rain"] && n["snow"]) {
        c.error(n["snow"], "weather.snow", "give rain or snow, not both");
    }
    if (const auto f = n["fog"]) {
        parse_fog(c, f, out);
    }
    if (const auto r = n["rain"]) {
        parse_precipitation(c, r, PrecipitationKind::rain, out);
    } else if (const auto s = n["snow"]) {
        parse_precipitation(c, s, PrecipitationKind::snow, out);
    }
    (void)number(c, n, "weather.", "wetness", out.wetness);
    (void)number(c, n, "weather.", "snow_cover", out.snow_cover);
    (void)number(c, n, "weather.", "overlap_start_m", out.overlap.start_m);
    (void)number(c, n, "weather.", "overlap_full_m", out.overlap.full_m);
    long cls = 0;
    if (n["medium_class"] && c.integer(n["medium_class"], "weather.medium_class", 0, 255, cls)) {
        out.medium_class = static_cast<std::uint8_t>(cls);
    }
    for (const std::string& problem : out.validate()) {
        const auto colon = problem.find(": ");
        c.error(node_of(n, problem.substr(0, colon)), problem.substr(0, colon),
                colon == std::string::npos ? problem : problem.substr(colon + 2));
    }
}

}  // namespace beamtrace::detail
