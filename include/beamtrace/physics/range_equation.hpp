// The monostatic laser-radar range equation for an extended target (one that fills the beam or
// sub-ray), and the mapping of received power to LAS intensity.
//
//   P_r = P_t * a * L(i) * A_r / (pi R^2) * eta * T^2,   T^2 = exp(-2 alpha R)
//
// P_t emitted peak power [W] (of the sub-ray: pulse power times the sub-ray's weight), a the
// albedo at the laser wavelength, L(i) = pi f_r cos(i) / a the monostatic reflectance factor of
// material.hpp for the configured BRDF (= cos i for a Lambertian surface, whose BRDF is a / pi;
// the 1/pi above is its), A_r = pi D^2 / 4 the receiver aperture area [m^2], R the range [m],
// eta the system (optics x detector) efficiency, alpha the atmospheric extinction [1/m] of
// atmosphere.hpp.
//
// LAS intensity (uint16) is linear in received power with a documented full scale:
//   intensity = round(65535 * min(1, P_r / P_fs)),  P_fs = P_t * A_r / (pi R_ref^2) * eta,
// i.e. a white (a = 1) Lambertian target facing the sensor at R_ref in vacuum reads 65535 and
// everything stronger saturates; a detected return (P_r > 0) reads at least 1. R_ref unset means
// kDefaultIntensityReferenceRange_m (10 m) here; a survey sets it to half its nominal range
// unless the survey file gives a number (docs/physics.md). `logarithmic` scaling instead maps
// [detection threshold, P_fs] to [1, 65535] linearly in decibels, for large dynamic ranges.
#pragma once

#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace beamtrace {

/// The R_ref of a RadiometryConfig whose intensity_reference_range_m is unset [m].
inline constexpr double kDefaultIntensityReferenceRange_m = 10.0;

enum class IntensityScale : std::uint8_t { linear, logarithmic };

/// "linear", "logarithmic".
[[nodiscard]] std::string_view to_string(IntensityScale scale);
/// The scale named `name`; throws ConfigError listing the choices.
[[nodiscard]] IntensityScale parse_intensity_scale(std::string_view name);

struct RadiometryConfig {
    double wavelength_nm = 1064.0;        ///< laser wavelength (materials, atmosphere)
    double peak_power_w = 1000.0;         ///< emitted peak power of one pulse, P_t
    double aperture_diameter_m = 0.05;    ///< receiver aperture diameter D
    double system_efficiency = 0.8;       ///< eta, in (0, 1]
    double detection_threshold_w = 1e-8;  ///< weakest detectable waveform peak (10 nW)
    /// R_ref of the LAS intensity full scale [m], > 0; unset: kDefaultIntensityReferenceRange_m
    /// (a survey replaces unset by half its nominal range, survey_reference_range).
    std::optional<double> intensity_reference_range_m;
    IntensityScale intensity_scale = IntensityScale::linear;

    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// R_ref in use: intensity_reference_range_m, or kDefaultIntensityReferenceRange_m when unset.
[[nodiscard]] double intensity_reference_range_m(const RadiometryConfig& config);

/// A_r = pi D^2 / 4.
[[nodiscard]] inline double aperture_area_m2(const RadiometryConfig& config) {
    return std::numbers::pi * config.aperture_diameter_m * config.aperture_diameter_m / 4.0;
}

/// P_r of the equation above. `reflectance_factor` is L(i) (monostatic_reflectance), `albedo`
/// is a, `transmission` is the two-way T^2. Returns 0 for range_m <= 0. (Inline: every sample
/// of every pulse asks it.)
[[nodiscard]] inline double received_power_w(const RadiometryConfig& config, double emitted_power_w,
                                             double albedo, double reflectance_factor,
                                             double range_m, double transmission) {
    if (!(range_m > 0)) {
        return 0.0;
    }
    return emitted_power_w * albedo * reflectance_factor * aperture_area_m2(config) /
           (std::numbers::pi * range_m * range_m) * config.system_efficiency * transmission;
}

/// The detection threshold [W] at which a data sheet's range figure holds ("260 m at 80 %
/// reflectivity"): P_r of an extended Lambertian target of albedo `reflectance` facing the
/// sensor (L = 1) at `range_m`, filling the beam, through the two-way `transmission`.
[[nodiscard]] double threshold_for_detection_range_w(const RadiometryConfig& config, double range_m,
                                                     double reflectance, double transmission);

/// P_fs: the received power that maps to LAS intensity 65535.
[[nodiscard]] double intensity_full_scale_w(const RadiometryConfig& config);

/// LAS intensity of a return of received (equivalent) power `power_w` (see the header comment).
[[nodiscard]] std::uint16_t las_intensity(const RadiometryConfig& config, double power_w);

}  // namespace beamtrace
