// A procedural albedo pattern on a material (the assignment's striped beach ball).
#pragma once

#include <cstdint>

namespace beamtrace {

enum class SurfacePatternKind : std::uint8_t { none, stripes, checker };

/// Where the pattern is "on", the albedo is `reflectance` instead of the material's. On analytic
/// spheres it follows the sphere's local frame: stripes are `count` segments in longitude about
/// the local z axis (a beach ball), a checker adds count/2 bands in latitude. On planes and
/// meshes it uses metres (segment 0 of a sphere starts at longitude -180 degrees): stripes of width
/// `size_m` along the plane's u axis (world x on meshes), a checker of `size_m` cells.
struct SurfacePattern {
    SurfacePatternKind kind = SurfacePatternKind::none;
    int count = 8;             ///< segments around a sphere, >= 2
    double size_m = 1.0;       ///< stripe width / checker cell on planes and meshes, > 0
    double reflectance = 0.1;  ///< albedo of the alternate segments, [0, 1]
};

}  // namespace beamtrace
