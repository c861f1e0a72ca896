// The weather of a survey (the survey file's `weather:` block, docs/weather.md): fog, rain or
// snow in the air (fog.hpp, precipitation.hpp) and wet or snow-covered surfaces (wetness.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/physics/fog.hpp"
#include "beamtrace/physics/precipitation.hpp"

namespace beamtrace {

/// Rain or snow falling at a rate.
struct PrecipitationConfig {
    PrecipitationKind kind = PrecipitationKind::rain;
    double rate_mm_h = 0.0;  ///< > 0; for snow, the rate of melted water
    /// Particle albedo; unset: default_particle_albedo(kind).
    std::optional<double> particle_albedo;
    /// Particles whose echo is weaker than this fraction of the detection threshold are not
    /// drawn (they still extinguish the beam); in (0, 1].
    double floor_fraction = 0.25;
};

/// What the weather produced a point's echo: the LAS extra byte `weather` (0 for none).
enum class WeatherEffect : std::uint8_t { none = 0, fog = 1, rain = 2, snow = 3 };

struct WeatherConfig {
    std::optional<FogConfig> fog;
    std::optional<PrecipitationConfig> precipitation;
    /// The sensor's blind zone and overlap ramp: no fog echo and no particle closer than
    /// overlap.start_m.
    OverlapConfig overlap;
    double wetness = 0.0;     ///< wetted fraction of every surface, [0, 1] (wetness.hpp)
    double snow_cover = 0.0;  ///< snow-covered fraction of every surface, [0, 1]
    /// LAS classification of a point whose echo came mostly from the medium (7: low noise).
    std::uint8_t medium_class = 7;

    /// Every problem with these settings, as `weather.key: what`; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
    /// True when nothing is in the air (no fog, no precipitation): the beam is the clear one.
    [[nodiscard]] bool clear_air() const { return !fog && !precipitation; }
};

/// The extinction [1/m] the weather adds to the air's: the fog's plus the precipitation's.
[[nodiscard]] double weather_extinction_per_m(const WeatherConfig& weather);

/// The effect of the particles of `kind`.
[[nodiscard]] WeatherEffect particle_effect(PrecipitationKind kind);

}  // namespace beamtrace
