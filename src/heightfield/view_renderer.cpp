#include "beamtrace/heightfield/view_renderer.hpp"

#include "beamtrace/heightfield/eye_dome.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "detail/grid_ray.hpp"
#include "detail/level_table.hpp"
#include "detail/view_beam.hpp"
#include "detail/view_trace_simd.hpp"

namespace beamtrace {
namespace {

using detail::cell_exits;
using detail::column_hit;
using detail::GridHit;
using detail::GridRay;
using detail::kInf;
using detail::LevelTable;

/// Hierarchical traversal: start at the root of the pyramid; on a potential hit descend to the
/// child under the ray; otherwise step to the next cell and climb while that step left the
/// parent (within the sections' levels at most streak / 2 levels, `streak` the steps since the
/// last descent: near the surface a walk that climbs as far as it may comes right back down).
/// Specialised on the signs of the ray's x, y and z directions (SX, SY: +1 or -1; DOWN: dz < 0),
/// with the same arithmetic as cell_exits and column_hit.
template <int SX, int SY, bool DOWN>
[[nodiscard]] bool trace_octant(const LevelTable& table, const GridRay& r, GridHit& hit) {
    // Start at the sections' coarsest level (starting at the root would cost every ray a
    // descent through the pyramid); steps climb into the pyramid where they leave a parent.
    const int top = table.root();
    const int section_top = table.section_top();
    int level = r.level < 0 ? section_top : r.level;
    std::int64_t cx = r.gx >> level, cy = r.gy >> level;
    double t = r.t_min;
    int entered = r.entered;
    int streak = 0;  // steps since the walk last met a potential hit
    constexpr std::int64_t kClimbX = SX > 0 ? 0 : 1;
    constexpr std::int64_t kClimbY = SY > 0 ? 0 : 1;
    const double ox = r.ox, oy = r.oy, oz = r.oz, dx = r.dx, dy = r.dy, dz = r.dz;
    const double inv_dx = r.inv_dx, inv_dy = r.inv_dy, t_max = r.t_max;
    for (;;) {
        const auto bx = static_cast<double>((SX > 0 ? cx + 1 : cx) << level);
        const auto by = static_cast<double>((SY > 0 ? cy + 1 : cy) << level);
        // A zero dx has SX = +1 and inv_dx = +inf, and bx > ox (the ray is inside the window
        // and its cell), so tx is +inf as in cell_exits without a test; the same for y.
        const double tx = (bx - ox) * inv_dx;
        const double ty = (by - oy) * inv_dy;
        const double t_out = std::min(tx, ty);
        const double t_end = std::min(t_out, t_max);
        const float h = table.height(level, cx, cy);
        const double z = DOWN ? oz + dz * t_end : oz + dz * t;
        if (z <= static_cast<double>(h)) {
            streak = 0;
            if (level > 0) {
                // The child under the ray at t: the upper half where the position is at or
                // past the middle (the same cell as the clamped floor of the scaled position;
                // scaling by a power of two is exact).
                --level;
                const double px = ox + dx * t;
                const double py = oy + dy * t;
                cx = 2 * cx +
                     static_cast<std::int64_t>(px >= static_cast<double>((2 * cx + 1) << level));
                cy = 2 * cy +
                     static_cast<std::int64_t>(py >= static_cast<double>((2 * cy + 1) << level));
                continue;
            }
            // With stacks the column's max only says the ray may meet an interval here.
            if (table.stacks() == 0 ||
                detail::stack_hit(r, t, t_end, table.stack(cx, cy), table.stacks(), hit)) {
                hit.x = cx;
                hit.y = cy;
                hit.t_in = t;
                hit.t_out = t_end;
                hit.entered_axis = entered;
                if (table.stacks() == 0) {
                    hit.h = h;
                    hit.bottom = false;
                }
                return true;
            }
        }
        if (t_out >= t_max) {
            return false;
        }
        t = t_out;
        const bool step_x = tx <= ty;
        const bool step_y = ty <= tx;
        if (step_x) {
            cx += SX;
        }
        if (step_y) {
            cy += SY;
        }
        entered = step_x ? 0 : 1;
        // Climb while the step crossed the parent's border: within the sections' levels
        // streak / 2 levels at most, into the pyramid above them only while its cell there is
        // empty (over data that would cost the ray a descent back through the pyramid for
        // nothing).
        const int cap = level + streak / 2;
        while (level < top &&
               ((step_x && (cx & 1) == kClimbX) || (step_y && (cy & 1) == kClimbY)) &&
               (level < section_top ? level < cap
                                    : table.height(level + 1, cx >> 1, cy >> 1) == kEmptyHeight)) {
            ++level;
            cx >>= 1;
            cy >>= 1;
        }
        ++streak;
        const std::int64_t cells = table.cells(level);
        if (cx < 0 || cy < 0 || cx >= cells || cy >= cells) {
            return false;
        }
    }
}

[[nodiscard]] inline bool trace_hierarchical(const LevelTable& table, const GridRay& r,
                                             GridHit& hit) {
    const bool down = r.dz < 0;
    if (r.sx > 0) {
        if (r.sy > 0) {
            return down ? trace_octant<1, 1, true>(table, r, hit)
                        : trace_octant<1, 1, false>(table, r, hit);
        }
        return down ? trace_octant<1, -1, true>(table, r, hit)
                    : trace_octant<1, -1, false>(table, r, hit);
    }
    if (r.sy > 0) {
        return down ? trace_octant<-1, 1, true>(table, r, hit)
                    : trace_octant<-1, 1, false>(table, r, hit);
    }
    return down ? trace_octant<-1, -1, true>(table, r, hit)
                : trace_octant<-1, -1, false>(table, r, hit);
}

/// Reference traversal: every finest cell along the ray, in order.
[[nodiscard]] inline bool trace_reference(const SectionGrid& grid, const GridRay& r, GridHit& hit) {
    std::int64_t cx = r.gx, cy = r.gy;
    const std::int64_t cells = grid.window_cells();
    const int stacks = grid.config().stacks();
    double t = r.t_min;
    int entered = -1;
    for (;;) {
        double tx, ty;
        cell_exits(r, cx, cy, 0, tx, ty);
        const double t_out = std::min(tx, ty);
        const double t_end = std::min(t_out, r.t_max);
        const float h = grid.height(0, cx, cy);
        if (column_hit(r, t, t_end, h) &&
            (stacks == 0 || detail::stack_hit(r, t, t_end, grid.stack(cx, cy), stacks, hit))) {
            hit.x = cx;
            hit.y = cy;
            hit.t_in = t;
            hit.t_out = t_end;
            hit.entered_axis = entered;
            if (stacks == 0) {
                hit.h = h;
                hit.bottom = false;
            }
            return true;
        }
        if (t_out >= r.t_max) {
            return false;
        }
        t = t_out;
        const bool step_x = tx <= ty;
        const bool step_y = ty <= tx;
        if (step_x) {
            cx += r.sx;
        }
        if (step_y) {
            cy += r.sy;
        }
        entered = step_x ? 0 : 1;
        if (cx < 0 || cy < 0 || cx >= cells || cy >= cells) {
            return false;
        }
    }
}

/// Shading of one pixel from its hit, or the sky.
class PixelSink {
  public:
    PixelSink(const SectionGrid& grid, const LevelTable& table, const RenderOptions& options,
              ViewImage& image, double oz)
        : grid_(grid),
          table_(table),
          options_(options),
          image_(image),
          per_two_cells_(2.0 * grid.config().cell_size),
          frame_(detail::shade_frame(grid, options, oz)) {}

    void hit(std::size_t i, const GridRay& r, const GridHit& hit) const {
        detail::shade_hit(
            grid_,
            [this](std::int64_t x, std::int64_t y, float* out) {
                table_.finest_neighbours(x, y, out);
            },
            per_two_cells_, r, hit, options_, image_.rgb.data() + 3 * i, image_.depth[i]);
    }
    /// hit() of the hits among rays[0, count) (found[j] != 0; miss() of the others), without
    /// height stacks, `lanes` at a time in SIMD lanes (detail::shade_lanes): the same image.
    void hits_in_lanes(int lanes, const GridRay* rays, const GridHit* hits,
                       const std::uint8_t* found, const std::size_t* pixels, std::size_t count,
                       detail::ShadeBatch& b) const {
        std::array<std::size_t, detail::kShadeBatch> slot;
        int m = 0;
        for (std::size_t j = 0; j < count; ++j) {
            if (found[j] == 0) {
                miss(pixels[j]);
                continue;
            }
            detail::gather_shade(grid_, table_, frame_.shading, rays[j], hits[j], b, m);
            slot[static_cast<std::size_t>(m)] = pixels[j];
            if (++m == detail::kShadeBatch) {
                shade_batch(lanes, b, slot.data(), m);
                m = 0;
            }
        }
        if (m > 0) {
            shade_batch(lanes, b, slot.data(), m);
        }
    }
    void miss(std::size_t i) const {
        std::uint8_t* out = image_.rgb.data() + 3 * i;
        out[0] = options_.sky[0];
        out[1] = options_.sky[1];
        out[2] = options_.sky[2];
        image_.depth[i] = std::numeric_limits<float>::infinity();
    }

  private:
    /// Shades the batch's m hits and writes them to their pixels slot[0, m).
    void shade_batch(int lanes, detail::ShadeBatch& b, const std::size_t* slot, int m) const {
        // The slots up to a whole number of lanes: copies of the last hit (shaded, not written).
        const int padded = (m + lanes - 1) / lanes * lanes;
        for (int k = m; k < padded; ++k) {
            detail::copy_shade_slot(b, m - 1, k);
        }
        detail::shade_lanes(lanes, frame_, b, padded);
        for (int k = 0; k < m; ++k) {
            const auto q = static_cast<std::size_t>(k);
            std::uint8_t* out = image_.rgb.data() + 3 * slot[q];
            out[0] = static_cast<std::uint8_t>(b.rgb[0][q]);
            out[1] = static_cast<std::uint8_t>(b.rgb[1][q]);
            out[2] = static_cast<std::uint8_t>(b.rgb[2][q]);
            image_.depth[slot[q]] = b.depth[q];
        }
    }
    const SectionGrid& grid_;
    const LevelTable& table_;
    const RenderOptions& options_;
    ViewImage& image_;
    detail::ExactDivisor per_two_cells_;
    detail::ShadeFrame frame_;
};

/// A rectangle of pixels [x0, x1) x [y0, y1) of an image `width` pixels wide.
struct Tile {
    int x0, y0, x1, y1, width;
};

/// A beam of pixels (`block`, at most kBeamPixels a side) with its rows' rays set up in lanes
/// (ray_setup_lanes) and their bounds.
struct LaneBeam {
    Tile block{};
    std::array<detail::RowDirections, detail::kBeamPixels> rows;
    detail::Beam beam;
    int entering = 0;  ///< bits of the lanes of any row whose rays enter the heights
};

/// The rays of a tile that enter the loaded heights, with their pixels, hits and whether they
/// hit: the thread's buffers, reused from tile to tile.
struct SimdBuffers {
    std::vector<GridRay> rays;
    std::vector<std::size_t> pixels;
    std::vector<GridHit> hits;
    std::vector<std::uint8_t> found;
    std::unique_ptr<detail::ShadeBatch> shade;  ///< for shading in lanes
    std::vector<LaneBeam> beams;                ///< a tile's beams, set up in lanes
};

/// The ray directions of a frame's pixels: one at a time (CameraRays::direction_at of the
/// pixel's column and row coordinates) or, with `lanes` > 1, a row of a beam at a time in SIMD
/// lanes with their clipping (detail::ray_setup_lanes: the same values).
struct PixelDirections {
    const CameraRays& rays;
    std::vector<double> u, v;  ///< image-plane coordinates per column and row
    detail::DirectionFrame frame;
    int lanes = 1;

    PixelDirections(const CameraRays& r, const ViewCamera& camera, double per_cell, int simd)
        : rays(r),
          u(static_cast<std::size_t>(camera.width)),
          v(static_cast<std::size_t>(camera.height)),
          lanes(simd) {
        for (int px = 0; px < camera.width; ++px) {
            u[static_cast<std::size_t>(px)] = rays.u(px);
        }
        for (int py = 0; py < camera.height; ++py) {
            v[static_cast<std::size_t>(py)] = rays.v(py);
        }
        frame = {rays.forward().x, rays.forward().y, rays.forward().z, rays.right().x,
                 rays.right().y,   rays.right().z,   rays.up().x,      rays.up().y,
                 rays.up().z,      per_cell};
    }

    /// Calls f(pixel index, ray) for the pixels [t.x0, t.x1) of row py whose rays `setup`
    /// clips to the loaded heights, miss(pixel index) for the others.
    template <typename Hit, typename Miss>
    void row(const detail::RaySetup& setup, const Tile& t, int py, Hit f, Miss miss) const {
        const std::size_t base = static_cast<std::size_t>(py) * static_cast<std::size_t>(t.width);
        if (lanes <= 1) {
            for (int px = t.x0; px < t.x1; ++px) {
                GridRay r;
                const auto i = base + static_cast<std::size_t>(px);
                const Vec3d d = rays.direction_at(u[static_cast<std::size_t>(px)],
                                                  v[static_cast<std::size_t>(py)]);
                setup(d, r) ? f(i, r) : miss(i);
            }
            return;
        }
        detail::RowDirections dirs;
        row_lanes(setup, t, py, dirs);
        const detail::ClipFrame c = setup.clip_frame();
        for (int k = 0; k < t.x1 - t.x0; ++k) {
            const auto i = base + static_cast<std::size_t>(t.x0 + k);
            if ((dirs.enter & (1 << k)) == 0) {
                miss(i);
                continue;
            }
            GridRay r;
            detail::lane_ray(c, dirs, k, r);
            f(i, r);
        }
    }

    /// detail::ray_setup_lanes of the pixels [t.x0, t.x1) of row py (lanes > 1).
    void row_lanes(const detail::RaySetup& setup, const Tile& t, int py,
                   detail::RowDirections& dirs) const {
        detail::ray_setup_lanes(lanes, frame, setup.clip_frame(), u.data() + t.x0,
                                v[static_cast<std::size_t>(py)], t.x1 - t.x0, dirs);
    }
};

/// Sets up the rows of `b.block` and their bounds.
void collect_beam_lanes(const PixelDirections& directions, const detail::RaySetup& setup,
                        LaneBeam& b) {
    const detail::ClipFrame c = setup.clip_frame();
    b.beam = {};
    b.entering = 0;
    // Every row set up first, then the bounds: the rows' divisions and square roots overlap,
    // where the bounds' loop (a branch per entering ray) between two rows held the next one back.
    for (int py = b.block.y0; py < b.block.y1; ++py) {
        directions.row_lanes(setup, b.block, py, b.rows[static_cast<std::size_t>(py - b.block.y0)]);
    }
    for (int py = b.block.y0; py < b.block.y1; ++py) {
        const detail::RowDirections& dirs = b.rows[static_cast<std::size_t>(py - b.block.y0)];
        b.entering |= dirs.enter;
        for (int left = dirs.enter; left != 0; left &= left - 1) {
            const int k = __builtin_ctz(static_cast<unsigned>(left));
            b.beam.add(c.ox, c.oy, c.oz, dirs.dx[k], dirs.dy[k], dirs.dz[k], dirs.t_min[k],
                       dirs.t_max[k]);
        }
    }
}

/// The rays of beam `b` from `start` (their jump to it in lanes, detail::start_rays_lanes) into
/// `buffers`, the others sky.
void emit_beam_lanes(int lanes, const detail::ClipFrame& c, const detail::BeamStart& start,
                     std::int64_t cells, LaneBeam& b, const PixelSink& sink, SimdBuffers& buffers) {
    const int n = b.block.x1 - b.block.x0;
    for (int py = b.block.y0; py < b.block.y1; ++py) {
        detail::RowDirections& dirs = b.rows[static_cast<std::size_t>(py - b.block.y0)];
        const std::size_t base =
            static_cast<std::size_t>(py) * static_cast<std::size_t>(b.block.width) +
            static_cast<std::size_t>(b.block.x0);
        const int go_on =
            dirs.enter != 0 ? detail::start_rays_lanes(lanes, c, start.t, cells, dirs) : 0;
        for (int k = 0; k < n; ++k) {
            if ((go_on & (1 << k)) == 0) {
                sink.miss(base + static_cast<std::size_t>(k));
                continue;
            }
            // Every field set here (not a value-initialised element then written: a `rep stos`
            // a ray, a quarter of this function's time).
            GridRay r;
            detail::lane_ray(c, dirs, k, r);
            r.entered = static_cast<int>(dirs.entered[k]);
            r.level = start.level;
            buffers.rays.push_back(r);
            buffers.pixels.push_back(base + static_cast<std::size_t>(k));
        }
    }
}

/// set_up_rays in SIMD lanes: the rows of every beam of the tile set up, then one coarse walk of
/// the tile's bounding beam (detail::beam_start) gives a distance before which no ray of the
/// tile meets a column; each beam's own walk starts there (its rays are among the tile's, so
/// its start stays conservative) and its rays jump to the beam's start in lanes.
void set_up_tile_lanes(const Tile& tile, const PixelDirections& directions,
                       const detail::RaySetup& setup, const LevelTable& table,
                       const PixelSink& sink, SimdBuffers& buffers) {
    constexpr int kBeam = detail::kBeamPixels;
    std::size_t count = 0;
    detail::Beam all;
    for (int by = tile.y0; by < tile.y1; by += kBeam) {
        for (int bx = tile.x0; bx < tile.x1; bx += kBeam) {
            if (buffers.beams.size() <= count) {
                buffers.beams.emplace_back();
            }
            LaneBeam& b = buffers.beams[count++];
            b.block = {bx, by, std::min(bx + kBeam, tile.x1), std::min(by + kBeam, tile.y1),
                       tile.width};
            collect_beam_lanes(directions, setup, b);
            if (b.entering != 0) {
                all.add(b.beam);
            }
        }
    }
    const double t_tile = count > 1 && all.t_lo < kInf ? detail::beam_start(table, all).t : 0.0;
    for (std::size_t j = 0; j < count; ++j) {
        LaneBeam& b = buffers.beams[j];
        detail::BeamStart start;
        if (b.entering != 0) {
            detail::Beam beam = b.beam;
            beam.t_lo = std::max(beam.t_lo, t_tile);
            start = detail::beam_start(table, beam);
        }
        emit_beam_lanes(directions.lanes, setup.clip_frame(), start, table.cells(0), b, sink,
                        buffers);
    }
}

/// Sets up the rays of the pixels of `tile` into `buffers` (sky for those that miss the loaded
/// heights), kBeamPixels x kBeamPixels at a time. With a `beams` table, the rays of each such
/// beam start where the first of them may meet a column (detail::beam_start) and those that end
/// before it are sky: the walk from there stops where it would have from the ray's start.
void set_up_rays(const Tile& tile, const PixelDirections& directions, const detail::RaySetup& setup,
                 const LevelTable* beams, const PixelSink& sink, SimdBuffers& buffers) {
    buffers.rays.clear();
    buffers.pixels.clear();
    constexpr int kBeam = detail::kBeamPixels;
    static_assert(kBeam <= detail::kRowDirections);
    if (beams != nullptr && directions.lanes > 1) {
        set_up_tile_lanes(tile, directions, setup, *beams, sink, buffers);
        return;
    }
    const auto miss = [&](std::size_t i) { sink.miss(i); };
    for (int by = tile.y0; by < tile.y1; by += kBeam) {
        for (int bx = tile.x0; bx < tile.x1; bx += kBeam) {
            const Tile block{bx, by, std::min(bx + kBeam, tile.x1), std::min(by + kBeam, tile.y1),
                             tile.width};
            const std::size_t first = buffers.rays.size();
            detail::Beam beam;
            for (int py = block.y0; py < block.y1; ++py) {
                directions.row(
                    setup, block, py,
                    [&](std::size_t i, const GridRay& r) {
                        beam.add(r);
                        buffers.rays.push_back(r);
                        buffers.pixels.push_back(i);
                    },
                    miss);
            }
            if (beams == nullptr || buffers.rays.size() == first) {
                continue;
            }
            const detail::BeamStart start = detail::beam_start(*beams, beam);
            const std::int64_t cells = beams->cells(0);
            std::size_t kept = first;
            for (std::size_t j = first; j < buffers.rays.size(); ++j) {
                if (detail::start_ray_at(buffers.rays[j], start.t, cells)) {
                    buffers.rays[j].level = start.level;
                    // Only once a ray was left out: a copy onto itself reads the fields just
                    // written in pieces, and waits for them (a store-forwarding stall).
                    if (kept != j) {
                        buffers.rays[kept] = buffers.rays[j];
                        buffers.pixels[kept] = buffers.pixels[j];
                    }
                    ++kept;
                } else {
                    sink.miss(buffers.pixels[j]);
                }
            }
            buffers.rays.resize(kept);
            buffers.pixels.resize(kept);
        }
    }
}

/// Reads the attribute (colour) of every hit cell once before shading: independent loads in a
/// short loop, so that their cache misses overlap (the shading of one pixel is too long for the
/// processor to reach the next pixel's attribute while the first waits), and the shading then
/// finds them in cache. The image is the same.
void touch_attributes(const SectionGrid& grid, const GridHit* hits, const std::uint8_t* found,
                      std::size_t count) {
    if (!color_mode_has_attribute(grid.config().color)) {
        return;
    }
    std::uint32_t all = 0;
    for (std::size_t j = 0; j < count; ++j) {
        all |= found[j] != 0 ? grid.attribute(hits[j].x, hits[j].y) : 0u;
    }
    // Keeps the loads (their values are not needed here).
    asm volatile("" : : "r"(all));
}

/// Renders the pixels of tiles [begin, end) (of `tiles_x` a row, `tile` pixels a side): their
/// rays set up by set_up_rays, traced in `lanes` SIMD lanes (or one at a time by `trace`),
/// shaded by `sink`. Returns the lanes of the kernel that ran.
template <typename Trace>
int render_tiles(const SectionGrid& grid, const LevelTable& table, const PixelDirections& direction,
                 const detail::RaySetup& setup, const PixelSink& sink, bool beams, Trace trace,
                 int lanes, int tile, int tiles_x, int width, int height, std::size_t begin,
                 std::size_t end) {
    // Reused by every tile of the chunk: one allocation each, not one per ray.
    SimdBuffers buffers;
    const auto most = static_cast<std::size_t>(tile) * static_cast<std::size_t>(tile);
    buffers.rays.reserve(most);
    buffers.pixels.reserve(most);
    buffers.hits.reserve(most);
    buffers.found.reserve(most);
    int ran = 1;
    for (std::size_t k = begin; k < end; ++k) {
        const int x0 = static_cast<int>(k % static_cast<std::size_t>(tiles_x)) * tile;
        const int y0 = static_cast<int>(k / static_cast<std::size_t>(tiles_x)) * tile;
        const Tile t{x0, y0, std::min(x0 + tile, width), std::min(y0 + tile, height), width};
        set_up_rays(t, direction, setup, beams ? &table : nullptr, sink, buffers);
        const std::size_t count = buffers.rays.size();
        buffers.hits.resize(count);
        buffers.found.resize(count);
        if (lanes > 1) {
            ran = detail::trace_rays_lanes(lanes, table, buffers.rays.data(), count,
                                           buffers.hits.data(), buffers.found.data());
        } else {
            for (std::size_t j = 0; j < count; ++j) {
                buffers.found[j] = trace(grid, table, buffers.rays[j], buffers.hits[j]) ? 1 : 0;
            }
        }
        touch_attributes(grid, buffers.hits.data(), buffers.found.data(), count);
        if (lanes > 1) {
            if (!buffers.shade) {
                buffers.shade = std::make_unique<detail::ShadeBatch>();
            }
            sink.hits_in_lanes(lanes, buffers.rays.data(), buffers.hits.data(),
                               buffers.found.data(), buffers.pixels.data(), count, *buffers.shade);
            continue;
        }
        for (std::size_t j = 0; j < count; ++j) {
            if (buffers.found[j] != 0) {
                sink.hit(buffers.pixels[j], buffers.rays[j], buffers.hits[j]);
            } else {
                sink.miss(buffers.pixels[j]);
            }
        }
    }
    return ran;
}

/// Renders `image` with `trace` (one ray at a time) or the kernel of `lanes` SIMD lanes; with
/// `beams`, rays start at their beam's start distance (set_up_rays).
template <typename Trace>
void render(const SectionGrid& grid, const ViewCamera& camera, const RenderOptions& options,
            ThreadPool& pool, Trace trace, int lanes, bool beams, ViewImage& image) {
    const LevelTable table(grid);
    camera.validate();
    image.width = camera.width;
    image.height = camera.height;
    const auto pixels =
        static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
    // Every pixel is written below: reusing the buffers of an image of the same size costs
    // nothing (fresh 14 MB per 1920x1080 frame cost page faults and a fill).
    image.rgb.resize(pixels * 3);
    image.depth.resize(pixels);
    const CameraRays rays(camera);
    const detail::RaySetup setup(grid, camera.position);
    // The reference sets up one ray at a time, the hierarchical renderer in its lanes.
    const PixelDirections direction(rays, camera, setup.per_cell(), beams ? lanes : 1);
    const PixelSink sink(grid, table, options, image, setup.clip_frame().oz);
    const int tile = std::max(1, options.tile_pixels);
    const int tiles_x = (camera.width + tile - 1) / tile;
    const int tiles_y = (camera.height + tile - 1) / tile;
    // The kernel each tile actually ran (every tile runs the same one): reported, not assumed.
    std::atomic<int> ran{1};
    // Four tiles a chunk: each chunk sets up its buffers once (about 2000 chunks a 1920x1080
    // frame, still plenty to balance two to a few dozen threads).
    pool.parallel_for(static_cast<std::size_t>(tiles_x) * static_cast<std::size_t>(tiles_y), 4,
                      [&](std::size_t begin, std::size_t end) {
                          const int r =
                              render_tiles(grid, table, direction, setup, sink, beams, trace, lanes,
                                           tile, tiles_x, camera.width, camera.height, begin, end);
                          if (r > 1) {
                              ran.store(r, std::memory_order_relaxed);
                          }
                      });
    image.kernel_lanes = ran.load();
    apply_eye_dome(image, options.eye_dome, pool);
}

}  // namespace

std::size_t ViewImage::hits() const {
    return static_cast<std::size_t>(
        std::count_if(depth.begin(), depth.end(), [](float d) { return std::isfinite(d); }));
}

ViewImage render_view(const SectionGrid& grid, const ViewCamera& camera,
                      const RenderOptions& options, ThreadPool& pool) {
    ViewImage image;
    render_view(grid, camera, options, pool, image);
    return image;
}

void render_view(const SectionGrid& grid, const ViewCamera& camera, const RenderOptions& options,
                 ThreadPool& pool, ViewImage& image) {
    // The widest kernel the CPU has, at most options.simd_lanes wide.
    int lanes = detail::widest_lanes();
    if (options.simd_lanes > 0) {
        lanes = options.simd_lanes >= 8 ? lanes : options.simd_lanes >= 4 ? std::min(lanes, 4) : 1;
    }
    if (grid.config().stacks() != 0) {
        lanes = 1;
    }
    render(
        grid, camera, options, pool,
        [](const SectionGrid&, const LevelTable& table, const GridRay& r, GridHit& h) {
            return trace_hierarchical(table, r, h);
        },
        lanes, true, image);
}

ViewImage render_view_reference(const SectionGrid& grid, const ViewCamera& camera,
                                const RenderOptions& options, ThreadPool& pool) {
    ViewImage image;
    render(
        grid, camera, options, pool,
        [](const SectionGrid& g, const LevelTable&, const GridRay& r, GridHit& h) {
            return trace_reference(g, r, h);
        },
        1, false, image);
    return image;
}

}  // namespace beamtrace
