// The hierarchical view traversal several rays at a time in SIMD lanes (AVX2: 4, AVX-512: 8),
// for CPUs that have them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>

#include "grid_ray.hpp"
#include "level_table.hpp"

namespace beamtrace::detail {

/// Lanes of the widest kernel this CPU runs: 8 (x86-64 with AVX-512 F, DQ and CD), 4 (AVX2) or
/// 1 (none: trace one ray at a time).
[[nodiscard]] int widest_lanes();

/// Traces rays[0, count) through `table` (which must have no height stacks) with the walk and
/// the arithmetic of the scalar traversal (start at the sections' coarsest level, descend on a
/// potential hit, step and climb otherwise, into the pyramid only over empty cells) in the
/// lanes of SIMD registers of `lanes` (4 or 8, at most widest_lanes()) 64-bit lanes, a lane
/// taking the next ray as soon as its ray ends: 8 rays a turn with AVX-512, and with AVX2 8 too,
/// in pairs of 4-lane registers (the walk waits on its height loads: 8 rays overlap them).
/// Each ray's sx and sy are RaySetup's: -1 where dx (dy) < 0, else 1. Sets found[i] (1: hit)
/// and, for hits, hits[i]: the same cell, distances and height as the scalar traversal, bit for
/// bit. Returns the register width that ran (8: AVX-512, 4: AVX2), which the renderer reports in
/// ViewImage::kernel_lanes.
[[nodiscard]] int trace_rays_lanes(int lanes, const LevelTable& table, const GridRay* rays,
                                   std::size_t count, GridHit* hits, std::uint8_t* found);

/// What the pixel directions of a frame depend on: CameraRays' forward, right and up vectors
/// and RaySetup::per_cell().
struct DirectionFrame {
    double fx = 0, fy = 0, fz = 0, rx = 0, ry = 0, rz = 0, ux = 0, uy = 0, uz = 0;
    double per_cell = 1;
};

/// The rays of up to kRowDirections pixels of one row, as RaySetup::operator() sets them up.
inline constexpr int kRowDirections = 8;
struct alignas(64) RowDirections {
    double dx[kRowDirections], dy[kRowDirections], dz[kRowDirections];
    double inv_dx[kRowDirections], inv_dy[kRowDirections], inv_dz[kRowDirections];
    /// RaySetup::clip's span and start cell (gx, gy as doubles, exact) of the rays in `enter`.
    double t_min[kRowDirections], t_max[kRowDirections], gx[kRowDirections], gy[kRowDirections];
    /// After start_rays_lanes: how the walk enters (gx, gy) at t_min (GridRay::entered).
    double entered[kRowDirections];
    int enter = 0;  ///< bit i: ray i enters the loaded heights (RaySetup::clip is true)
};

/// For pixels at image-plane coordinates (u[i], v), i < count <= kRowDirections: dx, dy and dz
/// of the ray along CameraRays::direction_at(u[i], v) in cells (dir.x * per_cell, dir.y *
/// per_cell, dir.z), inv_dx and inv_dy (1 / d, kInf for 0) and inv_dz = 1 / dz: the values
/// RaySetup::operator() works out; then RaySetup::clip's with `clip` (RaySetup::clip_frame()):
/// which rays enter (out.enter), their t_min, t_max, gx and gy. The same IEEE operations in the
/// same order (none fused) and the same choices on ties and signed zeros, so every value is the
/// scalar one bit for bit; `lanes` (4 or 8, at most widest_lanes()) rays at a time.
void ray_setup_lanes(int lanes, const DirectionFrame& frame, const ClipFrame& clip, const double* u,
                     double v, int count, RowDirections& out);

/// What RaySetup::clip sets in `r` (entered and level: the start), from the values of ray k
/// of `row` (ray_setup_lanes with `clip`).
inline void lane_ray(const ClipFrame& clip, const RowDirections& row, int k, GridRay& r) {
    r.ox = clip.ox;
    r.oy = clip.oy;
    r.oz = clip.oz;
    r.dx = row.dx[k];
    r.dy = row.dy[k];
    r.dz = row.dz[k];
    r.inv_dx = row.inv_dx[k];
    r.inv_dy = row.inv_dy[k];
    r.sx = r.dx < 0 ? -1 : 1;
    r.sy = r.dy < 0 ? -1 : 1;
    r.t_min = row.t_min[k];
    r.t_max = row.t_max[k];
    r.gx = static_cast<std::int64_t>(row.gx[k]);
    r.gy = static_cast<std::int64_t>(row.gy[k]);
}

/// start_ray_at (view_beam.hpp) of the rays of `rows` in rows.enter (their origin clip.ox,
/// clip.oy; their sx and sy the signs of dx and dy) at distance t in a window of `cells` a
/// side: moves their t_min, gx and gy and sets `entered` (-1 where the start stays) as
/// start_ray_at does, with the same products and comparisons bit for bit. Returns the bits of
/// the rays that go on (start_ray_at true); the others end before t (misses). `lanes` (4 or 8,
/// at most widest_lanes()) rays at a time.
[[nodiscard]] int start_rays_lanes(int lanes, const ClipFrame& clip, double t, std::int64_t cells,
                                   RowDirections& rows);

/// What shade_hit's arithmetic depends on besides the hit, for a frame without height stacks.
struct ShadeFrame {
    double oz = 0;  ///< the camera's height (every ray's origin)
    /// ExactDivisor(2 * cell size): x * per_two_inv where per_two_product, else x / per_two.
    double per_two = 2, per_two_inv = 0.5;
    bool per_two_product = true;
    double sun_x = 0, sun_y = 0, sun_z = 1;  ///< normalize(Vec3d(-0.4, -0.5, 1.0))
    bool shading = true;
    double fog_distance = 0;  ///< 0: no fog
    double sky[3] = {0, 0, 0};
};

/// Up to kShadeBatch hits (no height stacks), one array per field: what shade_hit reads of each
/// (with its ray's dz, sx and sy and, where shading is on, the four neighbours' heights as
/// doubles of the floats; the base colour's bytes as doubles). shade_lanes writes the depth
/// and the colour bytes (as int32) in place.
inline constexpr int kShadeBatch = 256;
struct alignas(64) ShadeBatch {
    double h[kShadeBatch], t_in[kShadeBatch], t_out[kShadeBatch], dz[kShadeBatch];
    double entered[kShadeBatch], sx[kShadeBatch], sy[kShadeBatch];
    double nb[4][kShadeBatch];  ///< (x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)
    double c[3][kShadeBatch];   ///< base colour
    float depth[kShadeBatch];
    std::int32_t rgb[3][kShadeBatch];
};

/// shade_hit of the hits batch[0, count) (count a multiple of `lanes`, the slots past the real
/// hits filled with copies of one of them): the same IEEE operations in the same order (no
/// products fused, std::exp one lane at a time) and the same choices of std::min, std::max and
/// std::clamp, so depth and colours are shade_hit's bit for bit; `lanes` (4 or 8, at most
/// widest_lanes()) hits at a time.
void shade_lanes(int lanes, const ShadeFrame& frame, ShadeBatch& batch, int count);

/// The ShadeFrame of `options` for rays from height oz (RaySetup::clip_frame().oz).
[[nodiscard]] inline ShadeFrame shade_frame(const SectionGrid& grid, const RenderOptions& options,
                                            double oz) {
    ShadeFrame f;
    f.oz = oz;
    f.per_two = 2.0 * grid.config().cell_size;
    f.per_two_product = ExactDivisor(f.per_two).is_product();
    f.per_two_inv = f.per_two_product ? 1.0 / f.per_two : 0.0;
    const Vec3d sun = sun_direction();
    f.sun_x = sun.x;
    f.sun_y = sun.y;
    f.sun_z = sun.z;
    f.shading = options.shading;
    f.fog_distance = options.fog_distance;
    for (std::size_t c = 0; c < 3; ++c) {
        f.sky[c] = static_cast<double>(options.sky[c]);
    }
    return f;
}

/// What shade_hit reads of hit `h` of ray `r` (no height stacks) into slot m of `b`: the
/// neighbours' heights only where `shading`.
inline void gather_shade(const SectionGrid& grid, const LevelTable& table, bool shading,
                         const GridRay& r, const GridHit& h, ShadeBatch& b, int m) {
    const auto k = static_cast<std::size_t>(m);
    b.h[k] = h.h;
    b.t_in[k] = h.t_in;
    b.t_out[k] = h.t_out;
    b.dz[k] = r.dz;
    b.entered[k] = h.entered_axis;
    b.sx[k] = r.sx;
    b.sy[k] = r.sy;
    const Rgb8 base = base_color(grid, h);
    for (std::size_t c = 0; c < 3; ++c) {
        b.c[c][k] = static_cast<double>(base[c]);
    }
    if (shading) {
        float nb[4];
        table.finest_neighbours(h.x, h.y, nb);
        for (std::size_t n = 0; n < 4; ++n) {
            b.nb[n][k] = static_cast<double>(nb[n]);
        }
    }
}

/// Copies slot `from` of `b`'s inputs to slot `to`.
inline void copy_shade_slot(ShadeBatch& b, int from, int to) {
    const auto f = static_cast<std::size_t>(from), t = static_cast<std::size_t>(to);
    for (double* a : {b.h, b.t_in, b.t_out, b.dz, b.entered, b.sx, b.sy, b.nb[0], b.nb[1], b.nb[2],
                      b.nb[3], b.c[0], b.c[1], b.c[2]}) {
        a[t] = a[f];
    }
}

}  // namespace beamtrace::detail
