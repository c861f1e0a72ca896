// A scene described in a file (YAML): parts with transforms, materials and labels. Parsed and
// validated here; turned into a triangle Scene by build_scene().
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/core/affine.hpp"
#include "beamtrace/core/crs.hpp"
#include "beamtrace/core/quat.hpp"
#include "beamtrace/core/vec3.hpp"
#include "beamtrace/geometry/rigid_motion.hpp"
#include "beamtrace/physics/material.hpp"

namespace beamtrace {

/// Scale, then rotate, then translate: p' = translate_m + R (scale * p).
struct PartTransform {
    Vec3d translate_m{0, 0, 0};
    /// Attitude in the report's convention (radians): the part's +x axis ends up where a sensor
    /// with this [roll pitch yaw] would look. Files give `rotate_deg: [roll, pitch, yaw]`.
    RollPitchYaw rotate;
    Vec3d scale{1, 1, 1};
    /// The mesh is y-up (`up_axis: y`): before everything else, (x, y, z) -> (x, -z, y), a
    /// quarter turn about +x that takes its +y to +z.
    bool y_up = false;

    [[nodiscard]] Vec3d apply(const Vec3d& p) const {
        const Vec3d q = y_up ? Vec3d{p.x, -p.z, p.y} : p;
        return translate_m +
               Quat::from_rpy(rotate).rotate({q.x * scale.x, q.y * scale.y, q.z * scale.z});
    }
    /// The same map as a matrix and a translation.
    [[nodiscard]] Affine3 to_affine() const;
};

/// Copies of a part on a regular grid: copy (i, j, k) is moved by i*step.x, j*step.y, k*step.z
/// (scene axes) after the part's own transform.
struct PartArray {
    std::array<long, 3> count{1, 1, 1};  ///< copies along x, y, z (each >= 1)
    Vec3d step_m{0, 0, 0};

    [[nodiscard]] std::uint64_t copies() const {
        return static_cast<std::uint64_t>(count[0]) * static_cast<std::uint64_t>(count[1]) *
               static_cast<std::uint64_t>(count[2]);
    }
};

/// `motion:` of a part (docs/scene-file.md): keyframes, or a constant velocity and spin. The
/// motion moves the part after its own transform (and each array copy by its step after that).
struct PartMotion {
    /// `keyframes:` (time_s, position_m, rotate_deg), strictly increasing in time; the key's pose
    /// places the part's transformed mesh. Empty: the constant motion below.
    std::vector<MotionKey> keys;
    Vec3d velocity_mps{0, 0, 0};   ///< `velocity_mps`
    Vec3d spin_axis{0, 0, 1};      ///< `spin.axis` (unit once parsed)
    double spin_rate_rad_s = 0.0;  ///< `spin.rate_rad_s` (right-handed about the axis)
    /// `spin.pivot_m`: the point the part spins about at time 0; none: its transform's
    /// translate_m (the part's origin).
    std::optional<Vec3d> pivot_m;
};

enum class PartKind : std::uint8_t { mesh, raster, sphere, plane };

struct PartSpec {
    std::string name;  ///< defaults to the file name or the kind and index
    PartKind kind = PartKind::mesh;
    std::filesystem::path file;   ///< mesh or raster file, relative to the scene file
    Vec3d center_m{0, 0, 0};      ///< sphere centre
    double radius_m = 1.0;        ///< sphere radius
    int sphere_subdivisions = 4;  ///< icosphere refinement (20 * 4^n triangles)
    /// Sphere traced exactly (one face ID per copy, native Embree geometry) instead of as an
    /// icosphere; needs a uniform scale.
    bool exact_sphere = false;
    Vec3d point_m{0, 0, 0};  ///< plane: a point on it (the centre of the square)
    Vec3d normal{0, 0, 1};   ///< plane: its normal (need not be unit)
    double size_m = 100.0;   ///< plane: side of the square patch
    PartTransform transform;
    PartArray array;                   ///< more than one copy makes the part instanced
    std::optional<PartMotion> motion;  ///< none: the part stays still
    std::string material = "default";
    std::uint8_t label = 1;     ///< LAS classification written for hits on this part
    std::uint16_t part_id = 0;  ///< LAS point source ID; defaults to the part's index + 1
};

struct SceneSpec {
    std::filesystem::path source;  ///< the scene file (for messages and relative paths)
    Vec3d origin_m{0, 0, 0};       ///< subtracted from raster coordinates (keeps floats precise)
    /// `crs:` (EPSG:<code> or OGC WKT); empty: the GeoTIFF rasters' own CRS, if any.
    Crs crs;
    /// The materials (physics Materials, docs/scene-file.md), "default" first.
    std::vector<Material> materials;
    std::vector<PartSpec> parts;

    [[nodiscard]] const Material* find_material(const std::string& name) const;
};

/// Parses a scene file. Throws ConfigError listing every problem as `file:line: key: what`.
[[nodiscard]] SceneSpec load_scene_spec(const std::filesystem::path& path);

/// The same from YAML text (`source` names it in messages and anchors relative paths).
[[nodiscard]] SceneSpec parse_scene_spec(const std::string& yaml_text,
                                         const std::filesystem::path& source);

}  // namespace beamtrace
