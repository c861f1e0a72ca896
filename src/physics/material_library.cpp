#include "beamtrace/physics/material_library.hpp"

#include <array>

namespace beamtrace {
namespace {

// Typical values; see the header for their provenance and uncertainty.
// name, 905 nm, 1064 nm, 1550 nm, specular weight, exponent, note
constexpr std::array kLibrary{
    NamedMaterial{"asphalt", 0.12, 0.13, 0.15, 0.0, 10.0, "aged road asphalt, dry"},
    NamedMaterial{"concrete", 0.35, 0.36, 0.33, 0.0, 10.0, "weathered grey concrete"},
    NamedMaterial{"grass", 0.45, 0.45, 0.22, 0.0, 10.0, "green lawn grass"},
    NamedMaterial{"vegetation", 0.50, 0.48, 0.25, 0.0, 10.0, "broadleaf foliage"},
    NamedMaterial{"conifer", 0.33, 0.32, 0.15, 0.0, 10.0, "needle-leaf canopy"},
    NamedMaterial{"soil", 0.30, 0.33, 0.40, 0.0, 10.0, "bare dry soil"},
    NamedMaterial{"snow", 0.85, 0.70, 0.05, 0.05, 20.0, "fresh snow (dark at 1550 nm)"},
    NamedMaterial{"water", 0.02, 0.02, 0.02, 0.9, 500.0, "calm water: mostly mirror-like"},
    NamedMaterial{"metal", 0.55, 0.55, 0.60, 0.6, 50.0, "brushed aluminium / galvanised steel"},
    NamedMaterial{"white_paint", 0.80, 0.78, 0.65, 0.1, 20.0, "road marking, white paint"},
    NamedMaterial{"car_paint", 0.30, 0.30, 0.28, 0.4, 200.0, "glossy automotive paint"},
    NamedMaterial{"brick", 0.40, 0.42, 0.45, 0.0, 10.0, "red clay brick"},
    NamedMaterial{"wood", 0.50, 0.50, 0.40, 0.0, 10.0, "dry untreated wood"},
    NamedMaterial{"glass", 0.05, 0.05, 0.05, 0.9, 1000.0, "window glass (mostly specular)"},
};

}  // namespace

std::span<const NamedMaterial> material_library() {
    return kLibrary;
}

double reflectance_at(const NamedMaterial& m, double wavelength_nm) {
    if (wavelength_nm <= 905.0) {
        return m.reflectance_905nm;
    }
    if (wavelength_nm <= 1064.0) {
        const double t = (wavelength_nm - 905.0) / (1064.0 - 905.0);
        return m.reflectance_905nm + t * (m.reflectance_1064nm - m.reflectance_905nm);
    }
    if (wavelength_nm <= 1550.0) {
        const double t = (wavelength_nm - 1064.0) / (1550.0 - 1064.0);
        return m.reflectance_1064nm + t * (m.reflectance_1550nm - m.reflectance_1064nm);
    }
    return m.reflectance_1550nm;
}

std::optional<Material> library_material(std::string_view name, double wavelength_nm) {
    for (const auto& m : kLibrary) {
        if (m.name == name) {
            Material out;
            out.name = std::string(m.name);
            out.reflectance = reflectance_at(m, wavelength_nm);
            out.specular_weight = m.specular_weight;
            out.specular_exponent = m.specular_exponent;
            return out;
        }
    }
    return std::nullopt;
}

std::string material_library_names() {
    std::string s;
    for (const auto& m : kLibrary) {
        s += (s.empty() ? "" : ", ") + std::string(m.name);
    }
    return s;
}

}  // namespace beamtrace
