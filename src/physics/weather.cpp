#include "beamtrace/physics/weather.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"

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

double max_detection_range_in_fog_m(const RadiometryConfig& radiometry, const AtmosphereConfig& air,
                                    double reflectance, double mor_m) {
    if (!(reflectance > 0.0 && reflectance <= 1.0)) {
        throw ConfigError("reflectance: must be in (0, 1], got " + std::to_string(reflectance));
    }
    if (!(mor_m > 0.0) || !std::isfinite(mor_m)) {
        throw ConfigError("mor_m: must be a positive number of metres, got " +
                          std::to_string(mor_m));
    }
    const double alpha = fog_extinction_per_m(FogConfig{mor_m, {}, {}}) +
                         extinction_per_m(air, radiometry.wavelength_nm);
    // ln K with K = R^2 exp(2 alpha R) at the root; in x = ln R: h(x) = 2 x + 2 alpha e^x - ln K,
    // increasing and convex, so Newton's method from x0 = ln K / 2 (the root without
    // extinction, never left of the root) falls monotonically onto it.
    const double log_k = std::log(radiometry.peak_power_w * reflectance *
                                  aperture_area_m2(radiometry) * radiometry.system_efficiency /
                                  (std::numbers::pi * radiometry.detection_threshold_w));
    double x = log_k / 2.0;
    for (int i = 0; i < 200; ++i) {
        const double e = alpha * std::exp(x);
        const double step = (2.0 * x + 2.0 * e - log_k) / (2.0 + 2.0 * e);
        x -= step;
        if (!(std::abs(step) > 1e-15 * std::max(1.0, std::abs(x)))) {
            break;
        }
    }
    return std::exp(x);
}

WeatherEffect particle_effect(PrecipitationKind kind) {
    return kind == PrecipitationKind::rain ? WeatherEffect::rain : WeatherEffect::snow;
}

}  // namespace beamtrace
