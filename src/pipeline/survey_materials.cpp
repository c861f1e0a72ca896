#include "pipeline/detail/survey_materials.hpp"

#include "beamtrace/core/error.hpp"
#include "beamtrace/physics/material_library.hpp"

namespace beamtrace::detail {

std::vector<Material> survey_materials(const Scene& scene, const PhysicsConfig& physics,
                                       const std::filesystem::path& scene_file) {
    std::vector<Material> materials;
    for (const auto& m : scene.materials) {
        Material pm;
        pm.name = m.name;
        pm.reflectance = m.reflectance;
        pm.specular_weight = m.specular_weight;
        pm.specular_exponent = m.specular_exponent;
        if (!m.library.empty()) {
            const auto lib = library_material(m.library, physics.radiometry.wavelength_nm);
            if (!lib) {
                throw ConfigError(scene_file.string() + ": material '" + m.name +
                                  "': unknown library material '" + m.library +
                                  "' (known: " + material_library_names() + ")");
            }
            pm = *lib;
            pm.name = m.name;
        }
        materials.push_back(pm);
    }
    return materials;
}

}  // namespace beamtrace::detail
