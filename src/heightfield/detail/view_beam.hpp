// Beams: a conservative start distance for a block of neighbouring pixel rays (8 x 8), from a
// coarse walk of the block's bounding beam over the maximum mipmap, and the jump of each ray's
// cell walk to that distance. The walk then stops in the same cell, at the same distance and
// through the same face as from the ray's start, so the image is the same bit for bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "grid_ray.hpp"
#include "level_table.hpp"

namespace beamtrace::detail {

/// Pixels per side of a beam.
inline constexpr int kBeamPixels = 8;

/// Bounds of the rays of a beam: every ray's cell-space direction lies in the box
/// [dx_lo, dx_hi] x [dy_lo, dy_hi] x [dz_lo, dz_hi] and its span [t_min, t_max] in
/// [t_lo, t_hi]. The rays share their origin (the camera).
struct Beam {
    double ox = 0, oy = 0, oz = 0;
    double dx_lo = kInf, dx_hi = -kInf, dy_lo = kInf, dy_hi = -kInf, dz_lo = kInf, dz_hi = -kInf;
    double t_lo = kInf, t_hi = -kInf;

    void add(const GridRay& r) { add(r.ox, r.oy, r.oz, r.dx, r.dy, r.dz, r.t_min, r.t_max); }
    /// The bounds of this beam's rays and of `b`'s (from the same origin).
    void add(const Beam& b) {
        add(b.ox, b.oy, b.oz, b.dx_lo, b.dy_lo, b.dz_lo, b.t_lo, b.t_hi);
        add(b.ox, b.oy, b.oz, b.dx_hi, b.dy_hi, b.dz_hi, b.t_lo, b.t_hi);
    }
    /// add() of a ray from (x, y, z) along (dx, dy, dz) over [t_min, t_max].
    void add(double x, double y, double z, double dx, double dy, double dz, double t_min,
             double t_max) {
        ox = x;
        oy = y;
        oz = z;
        dx_lo = std::min(dx_lo, dx);
        dx_hi = std::max(dx_hi, dx);
        dy_lo = std::min(dy_lo, dy);
        dy_hi = std::max(dy_hi, dy);
        dz_lo = std::min(dz_lo, dz);
        dz_hi = std::max(dz_hi, dz);
        t_lo = std::min(t_lo, t_min);
        t_hi = std::max(t_hi, t_max);
    }
};

/// Slack of the beam's tests, far above the rounding of the cell walk's arithmetic (about
/// 1e-16 relative): positions are widened by kBeamCellSlack cells, and a height must lie below
/// the beam by kBeamHeightSlack * (1 + |oz| + t).
inline constexpr double kBeamCellSlack = 1e-4;
inline constexpr double kBeamHeightSlack = 1e-7;

/// The highest column of `table` under the cells of `level` that meet [x0, x1] x [y0, y1]
/// (window cell coordinates; nothing outside the window), climbing to coarser levels while the
/// box spans more than three cells a side. kEmptyHeight where there is none.
[[nodiscard]] inline double beam_box_max(const LevelTable& table, int level, double x0, double x1,
                                         double y0, double y1) {
    const double window = static_cast<double>(table.cells(0));
    if (x1 < 0 || y1 < 0 || x0 >= window || y0 >= window) {
        return kEmptyHeight;
    }
    const std::int64_t last = table.cells(0) - 1;
    const std::int64_t fx0 = std::clamp(floor_to_int(std::max(x0, 0.0)), std::int64_t{0}, last);
    const std::int64_t fx1 = std::clamp(floor_to_int(std::min(x1, window)), std::int64_t{0}, last);
    const std::int64_t fy0 = std::clamp(floor_to_int(std::max(y0, 0.0)), std::int64_t{0}, last);
    const std::int64_t fy1 = std::clamp(floor_to_int(std::min(y1, window)), std::int64_t{0}, last);
    while (level < table.root() &&
           ((fx1 >> level) - (fx0 >> level) > 2 || (fy1 >> level) - (fy0 >> level) > 2)) {
        ++level;
    }
    float h = kEmptyHeight;
    for (std::int64_t y = fy0 >> level; y <= fy1 >> level; ++y) {
        for (std::int64_t x = fx0 >> level; x <= fx1 >> level; ++x) {
            h = std::max(h, table.height(level, x, y));
        }
    }
    return static_cast<double>(h);
}

/// Where the rays of a beam start: a distance before which none of them meets a column (kInf:
/// none does within its span), at least beam.t_lo, and the level their walks start at (the
/// finest whose cells were at least twice the beam's width there).
struct BeamStart {
    double t = 0;
    int level = 0;
};

/// The start of the rays of `beam`. Walks the beam's span in steps whose footprint (the box of
/// every ray's positions over the step) covers at most about two cells of the current level a side,
/// coarsening after a clear step and refining after a blocked one while the level's cells stay
/// at least twice the beam's width; stops at the first step blocked at the finest such level.
[[nodiscard]] inline BeamStart beam_start(const LevelTable& table, const Beam& b) {
    const auto cell = [](int level) { return static_cast<double>(std::int64_t{1} << level); };
    if (!(b.t_lo < b.t_hi)) {
        return {b.t_lo, table.section_top()};
    }
    const double ax = b.dx_hi - b.dx_lo, ay = b.dy_hi - b.dy_lo;
    const double bx = std::max(std::abs(b.dx_lo), std::abs(b.dx_hi));
    const double by = std::max(std::abs(b.dy_lo), std::abs(b.dy_hi));
    const double spread = std::max(ax, ay);
    const int root = table.root();
    double t = b.t_lo;
    int level = 0;
    for (int steps = 0; steps < 4096; ++steps) {
        while (level < root && 2.0 * spread * t > cell(level)) {
            ++level;
        }
        const double s = cell(level);
        // The step's end: its box is at most s wide along x and y (a * tb + b * (tb - t) <= s).
        double tb = std::min((s + bx * t) / (ax + bx), (s + by * t) / (ay + by));
        tb = std::min(tb, b.t_hi);
        if (!(tb > t)) {
            tb = b.t_hi;
        }
        const double x0 = b.ox + std::min(b.dx_lo * t, b.dx_lo * tb) - kBeamCellSlack;
        const double x1 = b.ox + std::max(b.dx_hi * t, b.dx_hi * tb) + kBeamCellSlack;
        const double y0 = b.oy + std::min(b.dy_lo * t, b.dy_lo * tb) - kBeamCellSlack;
        const double y1 = b.oy + std::max(b.dy_hi * t, b.dy_hi * tb) + kBeamCellSlack;
        const double z = b.oz + std::min(b.dz_lo * t, b.dz_lo * tb) -
                         kBeamHeightSlack * (1.0 + std::abs(b.oz) + tb);
        if (z > beam_box_max(table, level, x0, x1, y0, y1)) {
            t = tb;
            if (t >= b.t_hi) {
                return {kInf, 0};
            }
            level = std::min(level + 1, root);
            continue;
        }
        if (level == 0 || 2.0 * spread * t > cell(level - 1)) {
            return {t, std::min(level, table.section_top())};
        }
        --level;
    }
    return {t, std::min(level, table.section_top())};
}

/// Exit distance of column `c` along one axis of a ray (origin o, direction d, sign sd): the
/// arithmetic of cell_exits at the finest level.
[[nodiscard]] inline double axis_exit(std::int64_t c, double o, double d, double inv_d, int sd) {
    return d != 0 ? (static_cast<double>(sd > 0 ? c + 1 : c) - o) * inv_d : kInf;
}

/// Along one axis: the cell the walk from `start` is in at distance `t` (the first cell past
/// `start` whose exit is beyond t), and its entry distance (-kInf for `start` itself).
inline std::int64_t axis_cell_at(std::int64_t start, double o, double d, double inv_d, int sd,
                                 std::int64_t cells, double t, double& entry) {
    entry = -kInf;
    if (d == 0) {
        return start;
    }
    std::int64_t c = std::clamp(floor_to_int(o + d * t), std::int64_t{-1}, cells);
    if ((c - start) * sd < 0) {
        c = start;
    }
    while (c != start && axis_exit(c - sd, o, d, inv_d, sd) > t) {
        c -= sd;
    }
    while (axis_exit(c, o, d, inv_d, sd) <= t) {
        c += sd;
    }
    if (c != start) {
        entry = axis_exit(c - sd, o, d, inv_d, sd);
    }
    return c;
}

/// Moves the start of `r`'s walk to where the walk from its start is at distance `t` (a
/// distance before which it meets no column): the finest cell, the distance the walk entered it
/// at and the face it entered through, exactly as the walk works them out (its crossings are
/// the same products, taken in the same order). Unchanged when t <= r.t_min; false when the
/// ray ends before t (past t_max or out of the window of `cells` a side): a miss.
[[nodiscard]] inline bool start_ray_at(GridRay& r, double t, std::int64_t cells) {
    if (!(t > r.t_min)) {
        return true;
    }
    if (t >= r.t_max) {
        return false;
    }
    double ex = 0, ey = 0;
    const std::int64_t cx = axis_cell_at(r.gx, r.ox, r.dx, r.inv_dx, r.sx, cells, t, ex);
    const std::int64_t cy = axis_cell_at(r.gy, r.oy, r.dy, r.inv_dy, r.sy, cells, t, ey);
    if (cx < 0 || cy < 0 || cx >= cells || cy >= cells) {
        return false;
    }
    if (cx == r.gx && cy == r.gy) {
        return true;
    }
    // The last step crossed the later of the two entries; both at once on a tie (entered
    // through x, as the walk reports it).
    r.entered = ex >= ey ? 0 : 1;
    r.t_min = std::max(ex, ey);
    r.gx = cx;
    r.gy = cy;
    return true;
}

}  // namespace beamtrace::detail
