#include "beamtrace/physics/weather.hpp"

#include <cmath>

namespace beamtrace {

std::vector<std::string> WeatherConfig::validate() const {
    std::vector<std::string> p;
    if (fog) {
        for (const std::string& s : fog->validate()) {
            p.push_back("weather." + s);
        }
    }
    if (precipitation) {
        const PrecipitationConfig& r = *precipitation;
        const std::string key = "weather." + std::string(to_string(r.kind)) + ".";
        if (!(r.rate_mm_h > 0.0) || !std::isfinite(r.rate_mm_h)) {
            p.push_back(key + "rate_mm_h: must be a positive number of mm/h");
        } else if (r.rate_mm_h > 500.0) {
            p.push_back(key + "rate_mm_h: more than 500 mm/h has never been measured");
        }
        if (r.particle_albedo && !(*r.particle_albedo >= 0.0 && *r.particle_albedo <= 1.0)) {
            p.push_back(key + "particle_albedo: must be in [0, 1]");
        }
        if (!(r.floor_fraction > 0.0 && r.floor_fraction <= 1.0)) {
            p.push_back(key + "floor_fraction: must be in (0, 1]");
        }
    }
    for (const std::string& s : overlap.validate()) {
        p.push_back("weather." + s);
    }
    if (!(wetness >= 0.0 && wetness <= 1.0)) {
        p.emplace_back("weather.wetness: must be in [0, 1]");
    }
    if (!(snow_cover >= 0.0 && snow_cover <= 1.0)) {
        p.emplace_back("weather.snow_cover: must be in [0, 1]");
    }
    return p;
}

double weather_extinction_per_m(const WeatherConfig& weather) {
    double alpha = 0.0;
    if (weather.fog) {
        alpha += fog_extinction_per_m(*weather.fog);
    }
    if (weather.precipitation) {
        alpha += extinction_per_m(
            drop_size_distribution(weather.precipitation->kind, weather.precipitation->rate_mm_h));
    }
    return alpha;
}

WeatherEffect particle_effect(PrecipitationKind kind) {
    return kind == PrecipitationKind::rain ? WeatherEffect::rain : WeatherEffect::snow;
}

}  // namespace beamtrace
