#include "beamtrace/heightfield/view_renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "beamtrace/core/thread_pool.hpp"
#include "detail/grid_ray.hpp"

namespace beamtrace {
namespace {

using detail::cell_exits;
using detail::column_hit;
using detail::GridHit;
using detail::GridRay;

/// 2^-level for every level.
constexpr auto kInversePowersOfTwo = [] {
    std::array<double, kMaxSectionLevels + 1> v{};
    double x = 1.0;
    for (auto& e : v) {
        e = x;
        x *= 0.5;
    }
    return v;
}();

/// Hierarchical traversal: start at the coarsest level; on a potential hit descend to the child
/// under the ray; otherwise step to the next cell and climb while that step left the parent.
[[nodiscard]] inline bool trace_hierarchical(const SectionGrid& grid, const GridRay& r,
                                             GridHit& hit) {
    const int top = grid.layout().levels - 1;
    int level = top;
    std::int64_t cx = r.gx >> top, cy = r.gy >> top;
    double t = r.t_min;
    int entered = -1;
    for (;;) {
        double tx, ty;
        cell_exits(r, cx, cy, level, tx, ty);
        const double t_out = std::min(tx, ty);
        const double t_end = std::min(t_out, r.t_max);
        const float h = grid.height(level, cx, cy);
        if (column_hit(r, t, t_end, h)) {
            if (level == 0) {
                hit = {cx, cy, t, t_end, entered, h};
                return true;
            }
            --level;
            const double scale = kInversePowersOfTwo[static_cast<std::size_t>(level)];
            const auto fx = static_cast<std::int64_t>(std::floor((r.ox + r.dx * t) * scale));
            const auto fy = static_cast<std::int64_t>(std::floor((r.oy + r.dy * t) * scale));
            cx = std::clamp(fx, 2 * cx, 2 * cx + 1);
            cy = std::clamp(fy, 2 * cy, 2 * cy + 1);
            continue;
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
        // Climb while the step crossed the parent's border.
        while (level < top) {
            const bool crossed = (step_x && (cx & 1) == (r.sx > 0 ? 0 : 1)) ||
                                 (step_y && (cy & 1) == (r.sy > 0 ? 0 : 1));
            if (!crossed) {
                break;
            }
            ++level;
            cx >>= 1;
            cy >>= 1;
        }
        const std::int64_t cells = grid.window_cells() >> level;
        if (cx < 0 || cy < 0 || cx >= cells || cy >= cells) {
            return false;
        }
    }
}

/// Reference traversal: every finest cell along the ray, in order.
[[nodiscard]] inline bool trace_reference(const SectionGrid& grid, const GridRay& r, GridHit& hit) {
    std::int64_t cx = r.gx, cy = r.gy;
    const std::int64_t cells = grid.window_cells();
    double t = r.t_min;
    int entered = -1;
    for (;;) {
        double tx, ty;
        cell_exits(r, cx, cy, 0, tx, ty);
        const double t_out = std::min(tx, ty);
        const double t_end = std::min(t_out, r.t_max);
        const float h = grid.height(0, cx, cy);
        if (column_hit(r, t, t_end, h)) {
            hit = {cx, cy, t, t_end, entered, h};
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
ViewImage render(const SectionGrid& grid, const ViewCamera& camera, const RenderOptions& options,
                 ThreadPool& pool, Trace trace) {
    camera.validate();
    ViewImage image;
    image.width = camera.width;
    image.height = camera.height;
    const auto pixels =
        static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
    image.rgb.resize(pixels * 3);
    image.depth.assign(pixels, std::numeric_limits<float>::infinity());
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
                            trace(grid, r, hit)) {
                            detail::shade_hit(grid, r, hit, options, out, image.depth[i]);
                        } else {
                            out[0] = options.sky[0];
                            out[1] = options.sky[1];
                            out[2] = options.sky[2];
                        }
                    }
                }
            }
        });
    return image;
}

}  // namespace

std::size_t ViewImage::hits() const {
    return static_cast<std::size_t>(
        std::count_if(depth.begin(), depth.end(), [](float d) { return std::isfinite(d); }));
}

ViewImage render_view(const SectionGrid& grid, const ViewCamera& camera,
                      const RenderOptions& options, ThreadPool& pool) {
    return render(grid, camera, options, pool,
                  [](const SectionGrid& g, const GridRay& r, GridHit& h) {
                      return trace_hierarchical(g, r, h);
                  });
}

ViewImage render_view_reference(const SectionGrid& grid, const ViewCamera& camera,
                                const RenderOptions& options, ThreadPool& pool) {
    return render(grid, camera, options, pool,
                  [](const SectionGrid& g, const GridRay& r, GridHit& h) {
                      return trace_reference(g, r, h);
                  });
}

}  // namespace beamtrace
