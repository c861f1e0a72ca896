#include "pipeline/detail/survey_materials.hpp"

#include "beamtrace/core/error.hpp"
#include "beamtrace/physics/material_library.hpp"
#include "beamtrace/physics/wetness.hpp"

namespace beamtrace::detail {

std::vector<Material> survey_materials(const Scene& scene, const PhysicsConfig& physics,
                                       const std::filesystem::path& scene_file) {
    std::vector<Material> materials;
    materials.reserve(scene.materials.size());
    for (const Material& m : scene.materials) {
        Material pm = m;
        if (!m.library.empty()) {
            const auto lib = library_material(m.library, physics.radiometry.wavelength_nm);
            if (!lib) {
                throw ConfigError(scene_file.string() + ": material '" + m.name +
                                  "': unknown library material '" + m.library +
                                  "' (known: " + material_library_names() + ")");
            }
            pm.reflectance = lib->reflectance;
            pm.specular_weight = lib->specular_weight;
            pm.specular_exponent = lib->specular_exponent;
        }
        if (physics.weather) {  // wet surfaces, then snow on them (wetness.hpp)
            pm = snow_covered_material(wet_material(pm, physics.weather->wetness),
                                       physics.weather->snow_cover,
                                       physics.radiometry.wavelength_nm);
        }
        materials.push_back(pm);
    }
    return materials;
}

}  // namespace beamtrace::detail
