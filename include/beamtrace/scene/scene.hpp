// A scene: its triangles (unique meshes placed by instances, see SceneGeometry), the table of
// parts they came from (so a face ID leads back to a mesh file, label and material) and the
// materials (physics Materials: the one model of `render` and surveys).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "beamtrace/core/crs.hpp"
#include "beamtrace/core/quat.hpp"
#include "beamtrace/geometry/rigid_motion.hpp"
#include "beamtrace/geometry/scene_geometry.hpp"
#include "beamtrace/physics/material.hpp"

namespace beamtrace {

struct ScenePart {
    std::string name;              ///< file path or procedural part name
    std::uint32_t first_face = 0;  ///< global face IDs [first_face, first_face + face_count)
    std::uint32_t face_count = 0;
    std::uint8_t label = 1;      ///< class written as LAS classification (1 = unclassified)
    std::uint16_t part_id = 0;   ///< written as LAS point source ID
    std::uint32_t material = 0;  ///< index into Scene::materials
    /// Instances that make up the part (1 for a flat part; for exact spheres, the spheres).
    std::uint32_t instance_count = 0;
    /// Its first analytic copy in Scene::spheres (-1: none; an exact sphere part's copies follow
    /// in face order) and its analytic copy in Scene::planes (-1: none). They say what its
    /// material's pattern is laid on (pattern_frame); build_scene sets them.
    std::int64_t first_sphere = -1;
    std::int64_t plane = -1;
    /// Object (instance) number of its first copy: the scene's objects are numbered from 0 in
    /// part order, one per copy (a flat part is one object, an exact sphere one per sphere).
    std::uint32_t first_object = 0;
    bool moving = false;  ///< its copies are Scene::moving (placed at time 0 in `geometry`)
};

/// Exact copy of a sphere part, for renderers that trace spheres analytically: of each copy of an
/// exact sphere part (PartSpec::exact_sphere), and of other single sphere parts with a uniform
/// scale (whose triangles are in `geometry` too).
struct SceneSphere {
    Vec3d center_m{0, 0, 0};
    double radius_m = 1.0;
    Quat attitude;           ///< the part's rotation (orients albedo patterns)
    std::uint32_t part = 0;  ///< index into Scene::parts
};

/// Exact copy of a square plane part (as make_square builds it, after the part's transform).
struct ScenePlane {
    Vec3d point_m{0, 0, 0};
    Vec3d normal{0, 0, 1};  ///< unit
    Vec3d u_axis{1, 0, 0};  ///< unit, in the plane; the square's sides follow u and normal x u
    double size_m = 100.0;
    std::uint32_t part = 0;
};

struct Scene {
    SceneGeometry geometry;
    std::vector<ScenePart> parts;
    std::vector<Material> materials{Material{}};
    /// World position of the local origin: triangles are stored relative to it (float precision
    /// for UTM-sized coordinates) and outputs add it back.
    Vec3d origin_m{0, 0, 0};
    /// The coordinate reference system of world coordinates (origin_m included): the scene
    /// file's `crs:`, else its GeoTIFF rasters' EPSG code; empty when neither says.
    Crs crs;
    /// Analytic copies of sphere and plane parts (filled by build_scene; ignored by backends).
    std::vector<SceneSphere> spheres;
    std::vector<ScenePlane> planes;
    /// Parts with a `motion:`: their motions, and one moving instance per copy (mesh and face
    /// IDs as in `geometry`). They come after every still part, so their faces have the highest
    /// IDs. `geometry` holds them placed at time 0 (what render and scan show) until
    /// detach_moving().
    std::vector<RigidMotion> motions;
    std::vector<MovingInstance> moving;

    /// Appends a part whose triangles are copied in scene coordinates; its faces get the next
    /// IDs (consecutive flat parts share one mesh).
    void add_part(std::string name, const TriangleMesh& part);
    /// The same with its label, ID and material (first_face/face_count are filled in).
    void add_part(ScenePart meta, const TriangleMesh& part);
    /// Appends a part made of instances of the stored mesh `mesh` (see SceneGeometry::add_mesh),
    /// one per transform, without copying its triangles.
    void add_instanced_part(ScenePart meta, std::uint32_t mesh,
                            const std::vector<Affine3>& to_world);
    /// Appends a part made of exact spheres (their `face` is ignored: each gets the next ID).
    void add_sphere_part(ScenePart meta, const std::vector<ExactSphere>& balls);
    /// The surface `part`'s pattern is laid on at its face `face` (albedo_pattern.hpp): its
    /// analytic sphere or plane, or a solid for every other part.
    [[nodiscard]] PatternFrame pattern_frame(const ScenePart& part, std::uint32_t face) const;
    /// Appends a part whose copies move: mesh `mesh` placed by `motion` (of the motion's frame,
    /// `local`) and moved by each of `offsets`; placed at time 0 in `geometry` too.
    void add_moving_part(ScenePart meta, std::uint32_t mesh, const RigidMotion& motion,
                         const Affine3& local, const std::vector<Vec3d>& offsets);
    /// Takes the moving instances out of `geometry` (which then holds what stays still), for a
    /// tracer that places them at each ray's time (accel/moving_instances.hpp). The face
    /// queries below still answer for their faces.
    void detach_moving();
    /// Bounds of every moving instance over the times [t0, t1] (empty when none moves).
    [[nodiscard]] Aabb moving_bounds(double t0, double t1) const;
    /// The moving instance holding `face`, or nullptr when the face stays still.
    [[nodiscard]] const MovingInstance* moving_of_face(std::uint32_t face) const;
    /// Unit normal of face `face` at `point` (scene coordinates) at time `time_s`.
    [[nodiscard]] Vec3d normal_at(std::uint32_t face, const Vec3d& point, double time_s) const;
    /// Velocity (m/s) at time `time_s` of the surface point `point` of face `face` (0 when still).
    [[nodiscard]] Vec3d velocity_at(std::uint32_t face, const Vec3d& point, double time_s) const;
    /// The object number (ScenePart::first_object) of the copy that holds `face`.
    [[nodiscard]] std::uint32_t object_of_face(std::uint32_t face) const;
    /// Index of the part that holds `face` (binary search).
    [[nodiscard]] std::size_t part_of_face(std::uint32_t face) const;
    /// Triangles (instances counted as copies; exact spheres are not triangles).
    [[nodiscard]] std::uint64_t triangle_count() const { return geometry.triangle_count(); }
    /// Exact spheres (each one face).
    [[nodiscard]] std::uint64_t sphere_count() const { return geometry.spheres.size(); }
};

/// Loads and concatenates mesh files in order (face IDs 0-based over all of them).
[[nodiscard]] Scene load_scene_meshes(const std::vector<std::filesystem::path>& paths);

}  // namespace beamtrace
