// The weather of a survey (the survey file's `weather:` block, docs/weather.md): fog, rain or
// snow in the air (fog.hpp, precipitation.hpp) and wet or snow-covered surfaces (wetness.hpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/physics/atmosphere.hpp"
#include "beamtrace/physics/fog.hpp"
#include "beamtrace/physics/precipitation.hpp"
#include "beamtrace/physics/range_equation.hpp"

namespace beamtrace {

/// Rain or snow falling at a rate.
struct PrecipitationConfig {
    PrecipitationKind kind = PrecipitationKind::rain;
    double rate_mm_h = 0.0;  ///< > 0; for snow, the rate of melted water
    /// Particle albedo; unset: default_particle_albedo(kind).
    std::optional<double> particle_albedo;
    /// Particles whose echo is weaker than this fraction of the detection threshold are not
    /// drawn (they still extinguish the beam); in (0, 1].
    double floor_fraction = 0.5;
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

/// The maximum detection range [m] in fog: the range R at which an extended Lambertian target
/// of albedo `reflectance` (in (0, 1]) facing the sensor and filling the beam returns exactly
/// the detection threshold through fog of meteorological optical range `mor_m` (> 0):
///
///   P_t rho A_r eta exp(-2 (alpha_fog + alpha_air) R) / (pi R^2) = P_threshold
///
/// (range_equation.hpp), with alpha_fog = ln(20) / mor_m (fog.hpp: in fog it does not depend on
/// the wavelength) and alpha_air the extinction of `air` at `radiometry.wavelength_nm`
/// (atmosphere.hpp; 0 when disabled). P_t, A_r (from the aperture diameter), eta and the
/// threshold are `radiometry`'s (the physics config's). The left side falls strictly with R, so
/// the root is unique: R = W(alpha sqrt(K)) / alpha with K = P_t rho A_r eta / (pi P_threshold),
/// W the Lambert W function, solved here by Newton's method in ln R to full double precision
/// (sqrt(K) when alpha is 0). Throws ConfigError on a reflectance or MOR out of range.
[[nodiscard]] double max_detection_range_in_fog_m(const RadiometryConfig& radiometry,
                                                  const AtmosphereConfig& air, double reflectance,
                                                  double mor_m);

/// The effect of the particles of `kind`.
[[nodiscard]] WeatherEffect particle_effect(PrecipitationKind kind);

}  // namespace beamtrace
