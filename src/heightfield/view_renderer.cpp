#include "beamtrace/heightfield/view_renderer.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "detail/grid_ray.hpp"

namespace beamtrace {
namespace {

using detail::cell_exits;
using detail::column_hit;
using detail::GridHit;
using detail::GridRay;
using detail::kInf;

/// Most levels of the traversal: the sections' levels plus the window pyramid above them.
inline constexpr int kMaxTraceLevels = 48;

/// Heights for the hierarchical traversal, built once per frame: per level and window slot the
/// address of the loaded section's level (nullptr when not loaded), so a lookup is one table
/// read; and above the sections' coarsest level a max pyramid over the whole window up to a
/// single cell, so rays skip empty sections and empty parts of the window a few cells at a
/// time. Pyramid cells are maxima of their children like the sections' levels, so the
/// traversal stops in the same finest cell as without them.
class LevelTable {
  public:
    explicit LevelTable(const SectionGrid& grid)
        : n_(grid.sections_per_side()),
          top_(grid.layout().levels - 1),
          shift_(grid.layout().finest_shift()) {
        const SectionLayout& layout = grid.layout();
        const auto slots = static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_);
        base_.assign(static_cast<std::size_t>(top_ + 1) * slots, nullptr);
        stacks_ = grid.config().stacks();
        stack_base_.assign(slots, nullptr);
        for (std::size_t i = 0; i < slots; ++i) {
            const HeightSection* s = grid.loaded(static_cast<int>(i));
            if (s == nullptr) {
                continue;
            }
            if (stacks_ > 0) {
                stack_base_[i] = s->stack_data().data();
            }
            for (int l = 0; l <= top_; ++l) {
                base_[static_cast<std::size_t>(l) * slots + i] =
                    s->heights().data() + layout.level_offset(l);
            }
        }
        for (int l = 0; l <= top_; ++l) {
            cells_[static_cast<std::size_t>(l)] = grid.window_cells() >> l;
        }
        // The pyramid: level top_ + k has ceil(cells(top_) / 2^k) cells per side.
        std::int64_t below = cells_[static_cast<std::size_t>(top_)];
        root_ = top_;
        while (below > 1 && root_ + 1 < kMaxTraceLevels) {
            const std::int64_t c = (below + 1) / 2;
            const std::size_t off = pyramid_.size();
            pyramid_.resize(off + static_cast<std::size_t>(c * c), kEmptyHeight);
            float* out = pyramid_.data() + off;
            for (std::int64_t y = 0; y < 2 * c; ++y) {
                for (std::int64_t x = 0; x < 2 * c; ++x) {
                    if (x < below && y < below) {
                        float& v = out[(y >> 1) * c + (x >> 1)];
                        v = std::max(v, height(root_, x, y));
                    }
                }
            }
            ++root_;
            const auto k = static_cast<std::size_t>(root_ - top_ - 1);
            pyramid_offset_[k] = off;
            cells_[static_cast<std::size_t>(root_)] = c;
            below = c;
        }
    }

    /// The coarsest level (one cell, or the sections' top level when the window has one cell).
    [[nodiscard]] int root() const { return root_; }
    /// The sections' coarsest level.
    [[nodiscard]] int section_top() const { return top_; }
    /// Cells per side at `level` (the pyramid's last cells may reach beyond the window).
    [[nodiscard]] std::int64_t cells(int level) const {
        return cells_[static_cast<std::size_t>(level)];
    }
    [[nodiscard]] float height(int level, std::int64_t x, std::int64_t y) const {
        if (level > top_) {
            const auto k = static_cast<std::size_t>(level - top_ - 1);
            return pyramid_[pyramid_offset_[k] +
                            static_cast<std::size_t>(y * cells_[static_cast<std::size_t>(level)] +
                                                     x)];
        }
        const int sh = shift_ - level;
        const float* b = base_[static_cast<std::size_t>(level) * static_cast<std::size_t>(n_) *
                                   static_cast<std::size_t>(n_) +
                               static_cast<std::size_t>((y >> sh) * n_ + (x >> sh))];
        if (b == nullptr) {
            return kEmptyHeight;
        }
        const std::int64_t mask = (std::int64_t{1} << sh) - 1;
        return b[static_cast<std::size_t>(((y & mask) << sh) + (x & mask))];
    }

    /// Intervals per finest cell (0: no stacks).
    [[nodiscard]] int stacks() const { return stacks_; }
    /// The stack of finest cell (x, y) of a loaded section.
    [[nodiscard]] const float* stack(std::int64_t x, std::int64_t y) const {
        const float* b = stack_base_[static_cast<std::size_t>((y >> shift_) * n_ + (x >> shift_))];
        const std::int64_t mask = (std::int64_t{1} << shift_) - 1;
        return b + static_cast<std::size_t>((((y & mask) << shift_) + (x & mask)) * 2 * stacks_);
    }

  private:
    int n_;
    int top_;
    int stacks_ = 0;
    std::vector<const float*> stack_base_;
    int shift_;
    int root_ = 0;
    std::vector<const float*> base_;
    std::array<std::int64_t, kMaxTraceLevels> cells_{};
    std::array<std::size_t, kMaxTraceLevels> pyramid_offset_{};
    std::vector<float> pyramid_;
};

/// Hierarchical traversal: start at the root of the pyramid; on a potential hit descend to the
/// child under the ray; otherwise step to the next cell and climb while that step left the
/// parent. Specialised on the signs of the ray's x, y and z directions (SX, SY: +1 or -1; DOWN:
/// dz < 0), with the same arithmetic as cell_exits and column_hit.
template <int SX, int SY, bool DOWN>
[[nodiscard]] bool trace_octant(const LevelTable& table, const GridRay& r, GridHit& hit) {
    // Start at the sections' coarsest level (starting at the root would cost every ray a
    // descent through the pyramid); steps climb into the pyramid where they leave a parent.
    const int top = table.root();
    const int section_top = table.section_top();
    int level = section_top;
    std::int64_t cx = r.gx >> level, cy = r.gy >> level;
    double t = r.t_min;
    int entered = -1;
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
        // always, into the pyramid above them only while its cell there is empty (over data
        // that would cost the ray a descent back through the pyramid for nothing).
        while (level < top &&
               ((step_x && (cx & 1) == kClimbX) || (step_y && (cy & 1) == kClimbY)) &&
               (level < section_top || table.height(level + 1, cx >> 1, cy >> 1) == kEmptyHeight)) {
            ++level;
            cx >>= 1;
            cy >>= 1;
        }
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

template <typename Trace>
void render(const SectionGrid& grid, const ViewCamera& camera, const RenderOptions& options,
            ThreadPool& pool, Trace trace, ViewImage& image) {
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
    const int tile = std::max(1, options.tile_pixels);
    const int tiles_x = (camera.width + tile - 1) / tile;
    const int tiles_y = (camera.height + tile - 1) / tile;
    pool.parallel_for(
        static_cast<std::size_t>(tiles_x) * static_cast<std::size_t>(tiles_y), 1,
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t k = begin; k < end; ++k) {
                const int x0 = static_cast<int>(k % static_cast<std::size_t>(tiles_x)) * tile;
                const int y0 = static_cast<int>(k / static_cast<std::size_t>(tiles_x)) * tile;
                const int x1 = std::min(x0 + tile, camera.width);
                const int y1 = std::min(y0 + tile, camera.height);
                for (int py = y0; py < y1; ++py) {
                    for (int px = x0; px < x1; ++px) {
                        const std::size_t i =
                            static_cast<std::size_t>(py) * static_cast<std::size_t>(camera.width) +
                            static_cast<std::size_t>(px);
                        std::uint8_t* out = image.rgb.data() + 3 * i;
                        GridRay r;
                        GridHit hit;
                        if (detail::setup_ray(grid, camera.position, rays.direction(px, py), r) &&
                            trace(grid, table, r, hit)) {
                            detail::shade_hit(
                                grid,
                                [&table](std::int64_t x, std::int64_t y) {
                                    return table.height(0, x, y);
                                },
                                r, hit, options, out, image.depth[i]);
                        } else {
                            out[0] = options.sky[0];
                            out[1] = options.sky[1];
                            out[2] = options.sky[2];
                            image.depth[i] = std::numeric_limits<float>::infinity();
                        }
                    }
                }
            }
        });
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
    render(
        grid, camera, options, pool,
        [](const SectionGrid&, const LevelTable& table, const GridRay& r, GridHit& h) {
            return trace_hierarchical(table, r, h);
        },
        image);
}

ViewImage render_view_reference(const SectionGrid& grid, const ViewCamera& camera,
                                const RenderOptions& options, ThreadPool& pool) {
    ViewImage image;
    render(
        grid, camera, options, pool,
        [](const SectionGrid& g, const LevelTable&, const GridRay& r, GridHit& h) {
            return trace_reference(g, r, h);
        },
        image);
    return image;
}

}  // namespace beamtrace
