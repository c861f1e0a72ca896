#include "beamtrace/physics/range_equation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/name_table.hpp"

namespace beamtrace {

namespace {

constexpr NameTable<IntensityScale, 2> kIntensityScales{
    "intensity scale",
    {{{IntensityScale::linear, "linear"}, {IntensityScale::logarithmic, "logarithmic"}}}};

}  // namespace

std::string_view to_string(IntensityScale scale) {
    return kIntensityScales.to_string(scale);
}

IntensityScale parse_intensity_scale(std::string_view name) {
    return kIntensityScales.parse(name);
}

std::vector<std::string> RadiometryConfig::validate() const {
    std::vector<std::string> p;
    const auto positive = [&](double v, const char* what) {
        if (!(v > 0) || !std::isfinite(v)) {
            p.push_back(std::string("radiometry: ") + what + " must be positive");
        }
    };
    positive(wavelength_nm, "wavelength_nm");
    positive(peak_power_w, "peak_power_w");
    positive(aperture_diameter_m, "aperture_diameter_m");
    positive(detection_threshold_w, "detection_threshold_w");
    if (intensity_reference_range_m) {
        positive(*intensity_reference_range_m, "intensity_reference_range_m");
    }
    if (!(system_efficiency > 0 && system_efficiency <= 1)) {
        p.emplace_back("radiometry: system_efficiency must be in (0, 1]");
    }
    if (p.empty() && intensity_scale == IntensityScale::logarithmic &&
        !(intensity_full_scale_w(*this) > detection_threshold_w)) {
        p.emplace_back(
            "radiometry: logarithmic intensity needs the full scale above the detection "
            "threshold (lower intensity_reference_range_m or the threshold)");
    }
    return p;
}

double intensity_reference_range_m(const RadiometryConfig& config) {
    return config.intensity_reference_range_m.value_or(kDefaultIntensityReferenceRange_m);
}

double threshold_for_detection_range_w(const RadiometryConfig& config, double range_m,
                                       double reflectance, double transmission) {
    return received_power_w(config, config.peak_power_w, reflectance, 1.0, range_m, transmission);
}

double intensity_full_scale_w(const RadiometryConfig& config) {
    return received_power_w(config, config.peak_power_w, 1.0, 1.0,
                            intensity_reference_range_m(config), 1.0);
}

std::uint16_t las_intensity(const RadiometryConfig& config, double power_w) {
    const double fs = intensity_full_scale_w(config);
    double x = 0.0;
    if (config.intensity_scale == IntensityScale::linear) {
        if (!(power_w > 0)) {
            return 0;
        }
        // A detected return never reads 0 (LAS's "no intensity").
        x = std::max(1.0, 65535.0 * std::min(power_w / fs, 1.0));
    } else {
        if (!(power_w > 0)) {
            return 0;
        }
        const double lo = std::log(config.detection_threshold_w), hi = std::log(fs);
        x = 1.0 + 65534.0 * std::clamp((std::log(power_w) - lo) / (hi - lo), 0.0, 1.0);
    }
    return static_cast<std::uint16_t>(std::lround(x));
}

}  // namespace beamtrace
