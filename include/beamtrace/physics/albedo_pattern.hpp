// A procedural albedo pattern (the striped beach ball, a checkered floor) and the surface it is
// laid on. One pattern type and one evaluation, shared by `render` and the survey's physics:
// a point is mapped to cell coordinates by its surface (PatternFrame), and odd cells get the
// pattern's alternate reflectance.
//  - sphere (the exact/analytic copy of a sphere part, in its local frame): stripes are `count`
//    segments in longitude about the local z axis, segment 0 starting at longitude -180 degrees
//    (a beach ball); a checker adds max(count / 2, 1) bands in latitude.
//  - plane (a square plane part): stripes of width `size_m` along the plane's u axis, a checker
//    of `size_m` cells on (u, w).
//  - solid (every other part: meshes, rasters, arrayed or stretched spheres): scene coordinates,
//    stripes of width `size_m` along x, a 3-D checker of `size_m` cubes.
#pragma once

#include <cstdint>
#include <vector>

#include <cstdint>

#include "beamtrace/core/quat.hpp"
#include "beamtrace/core/vec3.hpp"

namespace beamtrace {

enum class AlbedoPatternKind : std::uint8_t {
    uniform,  ///< the material's reflectance everywhere (scene files: `kind: none`)
    stripes,  ///< alternating stripes (see above for each surface)
    checker,  ///< alternating cells
};

struct AlbedoPattern {
    AlbedoPatternKind kind = AlbedoPatternKind::uniform;
    int count = 8;                       ///< sphere: segments in longitude, >= 2
    double size_m = 1.0;                 ///< plane/solid: stripe width or checker cell, > 0
    double alternate_reflectance = 0.1;  ///< albedo of the odd stripes/cells, [0, 1]
    /// `render` only: the cells' colours in turn (cell k takes colors[k mod n], linear RGB in
    /// [0, 1]; the beach ball's stripes); empty: the material's colour everywhere.
    std::vector<Vec3d> colors;
};

/// The surface a pattern is laid on (see the file comment).
enum class PatternSurface : std::uint8_t { solid, sphere, plane };

struct PatternFrame {
    PatternSurface surface = PatternSurface::solid;
    Vec3d origin_m{0, 0, 0};  ///< sphere: its centre; plane: a point on it (the square's centre)
    double radius_m = 1.0;    ///< sphere: its radius
    Quat attitude;            ///< sphere: its local frame (the stripes' axis is local z)
    Vec3d u_axis{1, 0, 0};    ///< plane: unit, in the plane
    Vec3d w_axis{0, 1, 0};    ///< plane: unit, in the plane, normal x u

    [[nodiscard]] static PatternFrame sphere(const Vec3d& center_m, double radius_m,
                                             const Quat& attitude) {
        return {PatternSurface::sphere, center_m, radius_m, attitude, {1, 0, 0}, {0, 1, 0}};
    }
    [[nodiscard]] static PatternFrame plane(const Vec3d& point_m, const Vec3d& u_axis,
                                            const Vec3d& w_axis) {
        return {PatternSurface::plane, point_m, 1.0, Quat{}, u_axis, w_axis};
    }
};

/// The index of the cell of `pattern` holding `point_m` (scene coordinates, on the surface of
/// `frame`): the stripe or checker cell count from the pattern's origin; 0 for a uniform one.
[[nodiscard]] std::int64_t pattern_cell(const AlbedoPattern& pattern, const PatternFrame& frame,
                                        const Vec3d& point_m);

/// The colour at `point_m` of a material of colour `base` with `pattern`: colors[cell mod n],
/// or `base` when the pattern has no colours.
[[nodiscard]] Vec3d pattern_color(const AlbedoPattern& pattern, const PatternFrame& frame,
                                  const Vec3d& point_m, const Vec3d& base);

/// True when `point_m` (scene coordinates, on the surface of `frame`) lies in an odd cell of
/// `pattern`, whose albedo is the alternate reflectance; false for a uniform pattern.
[[nodiscard]] bool in_alternate_cell(const AlbedoPattern& pattern, const PatternFrame& frame,
                                     const Vec3d& point_m);

}  // namespace beamtrace
