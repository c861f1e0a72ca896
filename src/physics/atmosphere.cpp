#include "beamtrace/physics/atmosphere.hpp"

#include <cmath>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/name_table.hpp"

namespace beamtrace {

namespace {

constexpr NameTable<ExtinctionModel, 2> kExtinctionModels{
    "extinction model", {{{ExtinctionModel::kim, "kim"}, {ExtinctionModel::kruse, "kruse"}}}};

}  // namespace

std::string_view to_string(ExtinctionModel model) {
    return kExtinctionModels.to_string(model);
}

ExtinctionModel parse_extinction_model(std::string_view name) {
    return kExtinctionModels.parse(name);
}

std::vector<std::string> AtmosphereConfig::validate() const {
    std::vector<std::string> p;
    if (!(visibility_km > 0) || !std::isfinite(visibility_km)) {
        p.emplace_back("atmosphere: visibility_km must be positive");
    }
    if (!std::isfinite(extinction_per_m_override)) {
        p.emplace_back("atmosphere: extinction_per_m must be finite");
    }
    return p;
}

double extinction_exponent(ExtinctionModel model, double visibility_km) {
    const double v = visibility_km;
    if (v > 50.0) {
        return 1.6;
    }
    if (v > 6.0) {
        return 1.3;
    }
    if (model == ExtinctionModel::kruse) {
        return 0.585 * std::cbrt(v);
    }
    if (v > 1.0) {
        return 0.16 * v + 0.34;
    }
    if (v > 0.5) {
        return v - 0.5;
    }
    return 0.0;
}

double extinction_per_m(ExtinctionModel model, double visibility_km, double wavelength_nm) {
    const double alpha_550_per_km = 3.912 / visibility_km;
    const double q = extinction_exponent(model, visibility_km);
    return alpha_550_per_km * std::pow(wavelength_nm / 550.0, -q) / 1000.0;
}

double extinction_per_m(const AtmosphereConfig& config, double wavelength_nm) {
    if (!config.enabled) {
        return 0.0;
    }
    if (config.extinction_per_m_override >= 0.0) {
        return config.extinction_per_m_override;
    }
    return extinction_per_m(config.model, config.visibility_km, wavelength_nm);
}

double two_way_transmission_exponent(double extinction_per_m, double range_m) {
    return -2.0 * extinction_per_m * range_m;
}

double two_way_transmission(double extinction_per_m, double range_m) {
    return std::exp(two_way_transmission_exponent(extinction_per_m, range_m));
}

}  // namespace beamtrace
