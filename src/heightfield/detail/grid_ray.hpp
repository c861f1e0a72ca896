// Ray setup, hit test and shading shared by the hierarchical and the reference renderers, so
// that the two differ only in how they walk the cells.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "beamtrace/heightfield/section_grid.hpp"
#include "beamtrace/heightfield/view_renderer.hpp"

namespace beamtrace::detail {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// A ray in window cell coordinates: x, y in finest cells from the window corner; z in world
/// units above origin.z; t is the world distance along the (unit) ray.
struct GridRay {
    double ox = 0, oy = 0, oz = 0;
    double dx = 0, dy = 0, dz = 0;
    double inv_dx = 0, inv_dy = 0;
    int sx = 1, sy = 1;
    double t_min = 0, t_max = 0;
    std::int64_t gx = 0, gy = 0;  ///< finest cell at t_min
    /// How the walk entered cell (gx, gy) at t_min: -1 at the ray's start, 0 through an x face,
    /// 1 through a y face (after start_ray_at, detail/view_beam.hpp, moved the start on).
    int entered = -1;
    /// The level the hierarchical walk starts at (-1: the sections' coarsest); any level gives
    /// the same hit, a level near the surface fewer descents.
    int level = -1;
};

/// std::floor of a value well inside the int64 range, without a library call (the same result).
[[nodiscard]] inline std::int64_t floor_to_int(double v) {
    const auto i = static_cast<std::int64_t>(v);
    return i - static_cast<std::int64_t>(v < static_cast<double>(i));
}

/// std::lround of a value in [0, 255], without a library call (the same result: halves round
/// up).
[[nodiscard]] inline std::uint8_t round_byte(double v) {
    const auto i = static_cast<int>(v);
    return static_cast<std::uint8_t>(i + static_cast<int>(v - static_cast<double>(i) >= 0.5));
}

/// What RaySetup::clip works with besides the ray, for its copy in SIMD lanes
/// (ray_setup_lanes, view_trace_simd.hpp).
struct ClipFrame {
    double ox = 0, oy = 0, oz = 0;  ///< the camera: x, y in window cells, z above origin.z
    double w = 0;                   ///< window cells a side
    double zmax = 0;                ///< the highest loaded height (-inf: none loaded)
    double floor_dz = 0;            ///< height of the floor below the camera
    double last = 0;                ///< the window's last cell
};

/// Rays from one camera position into the window: what depends only on the frame is worked out
/// once (the window, its height range, the position in cells).
class RaySetup {
  public:
    RaySetup(const SectionGrid& grid, const Vec3d& position)
        : zmax_(grid.max_height()),
          zmin_(grid.min_height()),
          cell_(grid.config().cell_size),
          w_(static_cast<double>(grid.window_cells())),
          last_(grid.window_cells() - 1) {
        const Vec3d corner = grid.window_corner();
        ox_ = (position.x - corner.x) / cell_;
        oy_ = (position.y - corner.y) / cell_;
        oz_ = position.z - corner.z;
        per_cell_ = 1.0 / cell_;
        // A hair below the lowest height, so that rounding in oz + dz * t does not lose a
        // surface that lies exactly at it (flat ground seen at a grazing angle).
        floor_dz_ = zmin_ - 1e-9 * (1.0 + std::abs(zmin_)) - oz_;
    }

    /// Clips the ray along `dir` (unit) to the window box between the lowest and the highest
    /// loaded height; false when it misses.
    [[nodiscard]] bool operator()(const Vec3d& dir, GridRay& r) const {
        r.dx = dir.x * per_cell_;
        r.dy = dir.y * per_cell_;
        r.dz = dir.z;
        r.inv_dx = r.dx != 0 ? 1.0 / r.dx : kInf;
        r.inv_dy = r.dy != 0 ? 1.0 / r.dy : kInf;
        return clip(r, 1.0 / r.dz);
    }

    /// The rest of operator(), for a ray whose dx, dy, dz, inv_dx and inv_dy are set as there
    /// (by the SIMD set-up, trace_directions_lanes, with the same operations) and inv_dz = 1 / dz.
    [[nodiscard]] bool clip(GridRay& r, double inv_dz) const {
        const double zmax = zmax_;
        if (zmax == -kInf) {
            return false;
        }
        const double w = w_;
        r.ox = ox_;
        r.oy = oy_;
        r.oz = oz_;
        r.sx = r.dx < 0 ? -1 : 1;
        r.sy = r.dy < 0 ? -1 : 1;
        double t0 = 0.0, t1 = kInf;
        // Between the window's two sides along one axis; false when parallel and outside.
        const auto slab = [&](double o, double d, double inv_d) {
            if (d != 0) {
                const double a = (0.0 - o) * inv_d, b = (w - o) * inv_d;
                t0 = std::max(t0, std::min(a, b));
                t1 = std::min(t1, std::max(a, b));
                return true;
            }
            return o >= 0 && o < w;
        };
        if (!slab(r.ox, r.dx, r.inv_dx) || !slab(r.oy, r.dy, r.inv_dy)) {
            return false;
        }
        // inv_dz: +-inf for a level ray (not used then).
        if (r.oz > zmax) {
            if (r.dz >= 0) {
                return false;
            }
            t0 = std::max(t0, (zmax - r.oz) * inv_dz);
        }
        if (r.dz > 0) {
            t1 = std::min(t1, (zmax - r.oz) * inv_dz);
        } else if (r.dz < 0) {
            // Below the lowest loaded height there is nothing to hit (columns do not reach
            // down forever): an empty cell stays see-through even for near-vertical rays.
            t1 = std::min(t1, floor_dz_ * inv_dz);
        }
        if (!(t0 <= t1)) {  // equal: a ray that just touches the only height (a flat plateau)
            return false;
        }
        r.t_min = t0;
        r.t_max = t1;
        r.entered = -1;
        r.level = -1;
        r.gx = std::clamp(floor_to_int(r.ox + r.dx * t0), std::int64_t{0}, last_);
        r.gy = std::clamp(floor_to_int(r.oy + r.dy * t0), std::int64_t{0}, last_);
        return true;
    }

    /// 1 / cell size: dx = dir.x * per_cell(), dy = dir.y * per_cell().
    [[nodiscard]] double per_cell() const { return per_cell_; }
    /// The values clip() works with.
    [[nodiscard]] ClipFrame clip_frame() const {
        return {ox_, oy_, oz_, w_, zmax_, floor_dz_, static_cast<double>(last_)};
    }

  private:
    double zmax_, zmin_, cell_, w_;
    std::int64_t last_;
    double ox_ = 0, oy_ = 0, oz_ = 0;
    double per_cell_ = 1;  ///< 1 / cell size: directions in cells per unit by a product
    double floor_dz_ = 0;  ///< height of the floor below the camera
};

/// Exit distance of cell (cx, cy) of `level` along x and along y.
inline void cell_exits(const GridRay& r, std::int64_t cx, std::int64_t cy, int level, double& tx,
                       double& ty) {
    const auto bx = static_cast<double>((r.sx > 0 ? cx + 1 : cx) << level);
    const auto by = static_cast<double>((r.sy > 0 ? cy + 1 : cy) << level);
    tx = r.dx != 0 ? (bx - r.ox) * r.inv_dx : kInf;
    ty = r.dy != 0 ? (by - r.oy) * r.inv_dy : kInf;
}

/// Whether the ray's span [t_in, t_out] over a cell column reaches down to height h.
[[nodiscard]] inline bool column_hit(const GridRay& r, double t_in, double t_out, float h) {
    const double z = r.dz < 0 ? r.oz + r.dz * t_out : r.oz + r.dz * t_in;
    return z <= static_cast<double>(h);
}

/// The finest cell a ray stopped in.
struct GridHit {
    std::int64_t x = 0, y = 0;
    double t_in = 0, t_out = 0;
    int entered_axis = -1;  ///< 0: through an x face, 1: through a y face, -1: ray start
    float h = 0;            ///< top of the column (with stacks: of the interval hit)
    float lo = 0;           ///< with stacks: bottom of the interval hit
    bool bottom = false;    ///< with stacks: the ray entered the interval through its underside
};

/// Height stacks: whether the ray's span [t_in, t_out] over a cell meets one of its intervals
/// (`iv`: `k` lo/hi pairs, ascending, unused ones (+inf, -inf) at the end; the lowest reaches
/// down forever, so the ground stays solid), and if so which one: the first along the ray (the
/// highest one met for a ray going down, the lowest for one going up). Sets hit.h, hit.lo and
/// hit.bottom.
[[nodiscard]] inline bool stack_hit(const GridRay& r, double t_in, double t_out, const float* iv,
                                    int k, GridHit& hit) {
    const double za = r.oz + r.dz * t_in, zb = r.oz + r.dz * t_out;
    const double zlo = std::min(za, zb), zhi = std::max(za, zb);
    if (r.dz < 0) {
        for (int j = k - 1; j >= 0; --j) {
            const float lo = iv[2 * j], hi = iv[2 * j + 1];
            if (lo > hi) {
                continue;
            }
            const double lo_eff = j == 0 ? -kInf : static_cast<double>(lo);
            if (zlo <= static_cast<double>(hi) && zhi >= lo_eff) {
                hit.h = hi;
                hit.lo = lo;
                hit.bottom = false;
                return true;
            }
        }
        return false;
    }
    for (int j = 0; j < k; ++j) {
        const float lo = iv[2 * j], hi = iv[2 * j + 1];
        if (lo > hi) {
            return false;
        }
        const double lo_eff = j == 0 ? -kInf : static_cast<double>(lo);
        if (zlo <= static_cast<double>(hi) && zhi >= lo_eff) {
            hit.h = hi;
            hit.lo = lo;
            hit.bottom = r.dz > 0 && za < lo_eff;
            return true;
        }
    }
    return false;
}

/// x / d for a divisor d fixed for a frame, as a product x * (1 / d) where d is a power of two:
/// then 1 / d is exact, and the product and the quotient are the one rounding of the same number
/// x / 2^k, bit for bit (subnormal, infinite and NaN results included). A division otherwise.
class ExactDivisor {
  public:
    explicit ExactDivisor(double d) : d_(d) {
        int e = 0;
        if (std::isfinite(d) && std::frexp(d, &e) == 0.5 && e > -1000 && e < 1000) {
            inv_ = 1.0 / d;
        }
    }
    [[nodiscard]] double operator()(double x) const { return inv_ != 0 ? x * inv_ : x / d_; }
    /// Whether the division is a product.
    [[nodiscard]] bool is_product() const { return inv_ != 0; }

  private:
    double d_;
    double inv_ = 0;  ///< 1 / d where d is a power of two, else 0
};

/// The direction towards the light of the shading.
[[nodiscard]] inline Vec3d sun_direction() {
    return normalize(Vec3d(-0.4, -0.5, 1.0));
}

/// The colour of a hit before its shading and fog: the height's ramp or the cell's attribute.
[[nodiscard]] inline Rgb8 base_color(const SectionGrid& grid, const GridHit& hit) {
    const ColorMode mode = grid.config().color;
    if (mode == ColorMode::height) {
        const double h = hit.h;
        const double lo = grid.min_height(), hi = grid.max_height();
        return height_ramp(hi > lo ? (h - lo) / (hi - lo) : 0.5);
    }
    const std::uint32_t a = grid.attribute(hit.x, hit.y);
    // RGB inline (attribute_color's first case, the bytes of the attribute): the common mode
    // without a call per pixel.
    return mode == ColorMode::rgb
               ? Rgb8{static_cast<std::uint8_t>(a >> 16), static_cast<std::uint8_t>(a >> 8),
                      static_cast<std::uint8_t>(a)}
               : attribute_color(mode, a, grid.intensity_full_scale());
}

/// Colour and distance of a hit. `neighbours(x, y, out)` sets out[0..3] to grid.height(0, ...)
/// of cells (x + 1, y), (x - 1, y), (x, y + 1) and (x, y - 1), kEmptyHeight outside the window
/// (LevelTable::finest_neighbours: a faster lookup of the same values); `per_two_cells` divides
/// by 2 * cell size.
template <typename Neighbours>
inline void shade_hit(const SectionGrid& grid, const Neighbours& neighbours,
                      const ExactDivisor& per_two_cells, const GridRay& r, const GridHit& hit,
                      const RenderOptions& options, std::uint8_t* rgb, float& depth) {
    const double h = hit.h;
    double t = hit.t_in;
    bool top = true;
    if (hit.bottom) {
        t = std::clamp((static_cast<double>(hit.lo) - r.oz) / r.dz, hit.t_in, hit.t_out);
        top = false;
    } else if (r.dz < 0) {
        const double t_top = (h - r.oz) / r.dz;
        if (t_top > hit.t_in) {
            t = std::min(t_top, hit.t_out);
        } else {
            top = hit.entered_axis < 0;
        }
    } else {
        top = hit.entered_axis < 0;
    }
    depth = static_cast<float>(t);

    const Rgb8 base = base_color(grid, hit);
    // Three scalars, not an array: GCC vectorised the array's loops into a 16-byte and an
    // 8-byte store read back as one 16-byte load, which waited for both (a store-forwarding
    // stall, a quarter of the shading's time). The same operations in the same order.
    double c0 = static_cast<double>(base[0]);
    double c1 = static_cast<double>(base[1]);
    double c2 = static_cast<double>(base[2]);
    if (options.shading) {
        Vec3d n;
        if (hit.bottom) {
            n = {0.0, 0.0, -1.0};
        } else if (top) {
            // With stacks, a neighbour whose top is far above (a bridge over the ground) is not
            // part of this surface; outside the window and where nothing is, the cell's own.
            const double above = grid.config().stacks() > 0
                                     ? static_cast<double>(grid.config().stack_gap_or_default())
                                     : kInf;
            float nb[4];
            neighbours(hit.x, hit.y, nb);
            const auto at = [&](float v) {
                return v == kEmptyHeight || static_cast<double>(v) > h + above
                           ? h
                           : static_cast<double>(v);
            };
            const double gx = per_two_cells(at(nb[0]) - at(nb[1]));
            const double gy = per_two_cells(at(nb[2]) - at(nb[3]));
            n = normalize(Vec3d(-gx, -gy, 1.0));
        } else if (hit.entered_axis == 0) {
            n = {static_cast<double>(-r.sx), 0.0, 0.0};
        } else {
            n = {0.0, static_cast<double>(-r.sy), 0.0};
        }
        const Vec3d sun = sun_direction();
        const double light = 0.35 + 0.65 * std::max(0.0, dot(n, sun));
        c0 *= light;
        c1 *= light;
        c2 *= light;
    }
    if (options.fog_distance > 0) {
        const double f = 1.0 - std::exp(-t / options.fog_distance);
        c0 = c0 * (1.0 - f) + static_cast<double>(options.sky[0]) * f;
        c1 = c1 * (1.0 - f) + static_cast<double>(options.sky[1]) * f;
        c2 = c2 * (1.0 - f) + static_cast<double>(options.sky[2]) * f;
    }
    rgb[0] = round_byte(std::clamp(c0, 0.0, 255.0));
    rgb[1] = round_byte(std::clamp(c1, 0.0, 255.0));
    rgb[2] = round_byte(std::clamp(c2, 0.0, 255.0));
}

}  // namespace beamtrace::detail
