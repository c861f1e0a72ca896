// Atmospheric extinction of the laser beam from the meteorological visibility.
//
// Koschmieder: the extinction at 550 nm is 3.912 / V (V the visibility, 2 % contrast threshold).
// At other wavelengths the empirical power law of Kruse (1962) / Kim et al. (SPIE 4214, 2001):
//   alpha(lambda) = (3.912 / V) * (lambda / 550 nm)^(-q)   [per km]
//   Kim:   q = 1.6 (V > 50 km), 1.3 (6 < V <= 50), 0.16 V + 0.34 (1 < V <= 6),
//          V - 0.5 (0.5 < V <= 1), 0 (V <= 0.5 km: fog, no wavelength dependence)
//   Kruse: q = 1.6 (V > 50 km), 1.3 (6 < V <= 50), 0.585 V^(1/3) (V <= 6)
// The one-way transmission over R metres is exp(-alpha R); a monostatic LiDAR sees it twice.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace beamtrace {

enum class ExtinctionModel : std::uint8_t { kim, kruse };

/// "kim", "kruse".
[[nodiscard]] std::string_view to_string(ExtinctionModel model);
/// The model named `name`; throws ConfigError listing the choices.
[[nodiscard]] ExtinctionModel parse_extinction_model(std::string_view name);

struct AtmosphereConfig {
    bool enabled = true;          ///< false: vacuum (transmission 1)
    double visibility_km = 23.0;  ///< meteorological visibility; 23 km = "clear" standard
    ExtinctionModel model = ExtinctionModel::kim;
    /// >= 0 overrides the visibility model with this extinction coefficient (per metre).
    double extinction_per_m_override = -1.0;

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// The size-distribution exponent q of the chosen model at visibility `visibility_km`.
[[nodiscard]] double extinction_exponent(ExtinctionModel model, double visibility_km);

/// Extinction coefficient alpha in 1/m at `wavelength_nm` for visibility `visibility_km`.
[[nodiscard]] double extinction_per_m(ExtinctionModel model, double visibility_km,
                                      double wavelength_nm);

/// The extinction coefficient the config gives at `wavelength_nm` (0 when disabled).
[[nodiscard]] double extinction_per_m(const AtmosphereConfig& config, double wavelength_nm);

/// -2 alpha R: the exponent of two_way_transmission (the survey's sub-rays take its exp in lanes).
[[nodiscard]] double two_way_transmission_exponent(double extinction_per_m, double range_m);
/// Two-way transmission exp(-2 alpha R) of a monostatic path of one-way length `range_m`.
[[nodiscard]] double two_way_transmission(double extinction_per_m, double range_m);

}  // namespace beamtrace
