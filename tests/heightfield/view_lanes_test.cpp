// The SIMD lanes of the view traversal round like the scalar walk: rays built to touch a flat
// terrain's top within a rounding error at the end of their first cell, where a fused
// multiply-add (oz + dz * t in one rounding) and the scalar walk's two roundings decide the hit
// differently. The AVX-512 kernel (compiled for a target that has FMA) must agree with the AVX2
// one (which has none) on every ray.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <utility>
#include <vector>

#include "beamtrace/heightfield/view_camera.hpp"
#include "heightfield/detail/view_beam.hpp"
#include "heightfield/detail/view_trace_simd.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// A window of 2 x 2 sections of `section_cells` a side at their coarsest of 3 levels.
HeightFieldConfig small_window(double cell_size, int section_cells) {
    HeightFieldConfig c;
    c.cell_size = cell_size;
    c.levels = 3;
    c.section_cells = section_cells;
    c.sections = 2;
    return c;
}

TEST(ViewLanes, Avx512KernelRoundsLikeTheScalarWalkWhereARayTouchesATop) {
    if (detail::widest_lanes() < 8) {
        BEAMTRACE_SKIP_HARDWARE("no AVX-512 on this CPU");
    }
    const HeightFieldConfig c = small_window(1.0, 4);
    SectionGrid grid(c, {0, 0, 0});
    const double h = 2.0;
    test::fill_grid(grid, [&](std::int64_t, std::int64_t) { return h; });
    const detail::LevelTable table(grid);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<detail::GridRay> rays;
    for (int i = 0; i < 4000; ++i) {
        const Vec3d dir = normalize(Vec3d{0.2 + u(rng), 0.2 + u(rng), -0.05 - u(rng)});
        detail::GridRay r;
        r.ox = 4.0 + 20.0 * u(rng);
        r.oy = 4.0 + 20.0 * u(rng);
        r.dx = dir.x;
        r.dy = dir.y;
        r.dz = dir.z;
        r.inv_dx = 1.0 / r.dx;
        r.inv_dy = 1.0 / r.dy;
        r.gx = static_cast<std::int64_t>(r.ox);
        r.gy = static_cast<std::int64_t>(r.oy);
        // The ray's height at the end of its first cell is the top, up to a rounding.
        const double t_end = std::min((static_cast<double>(r.gx + 1) - r.ox) * r.inv_dx,
                                      (static_cast<double>(r.gy + 1) - r.oy) * r.inv_dy);
        // A few units in the last place either way: the roundings decide.
        r.oz = h - r.dz * t_end;
        for (int k = static_cast<int>(7.0 * u(rng)) - 3; k != 0; k += k > 0 ? -1 : 1) {
            r.oz = std::nextafter(r.oz, k > 0 ? 100.0 : -100.0);
        }
        r.t_min = 0.0;
        r.t_max = t_end + 4.0;
        rays.push_back(r);
    }
    std::vector<detail::GridHit> h8(rays.size()), h4(rays.size());
    std::vector<std::uint8_t> f8(rays.size()), f4(rays.size());
    ASSERT_EQ(detail::trace_rays_lanes(8, table, rays.data(), rays.size(), h8.data(), f8.data()),
              8);
    ASSERT_EQ(detail::trace_rays_lanes(4, table, rays.data(), rays.size(), h4.data(), f4.data()),
              4);
    int first_cell = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(f8[i], f4[i]) << i;
        ASSERT_EQ(f8[i], 1) << i;
        EXPECT_EQ(h8[i].x, h4[i].x) << i;
        EXPECT_EQ(h8[i].y, h4[i].y) << i;
        EXPECT_EQ(h8[i].t_in, h4[i].t_in) << i;
        first_cell += h4[i].x == rays[i].gx && h4[i].y == rays[i].gy ? 1 : 0;
    }
    // Both outcomes occur: the touches are decided by the last bit.
    std::printf("[ touches  ] %d of %zu rays hit their first cell\n", first_cell, rays.size());
    EXPECT_GT(first_cell, 100);
    EXPECT_LT(first_cell, 3900);
}

TEST(ViewLanes, FinestNeighboursAreTheFinestHeightsAroundACell) {
    const HeightFieldConfig c = small_window(1.0, 2);
    SectionGrid grid(c, {0, 0, 0});
    test::fill_grid(
        grid, [](std::int64_t x, std::int64_t y) { return static_cast<double>(x * 100 + y); });
    const detail::LevelTable table(grid);
    const std::int64_t w = grid.window_cells();
    ASSERT_GT(w, 8);
    int read = 0;
    for (std::int64_t y = 0; y < w; ++y) {
        for (std::int64_t x = 0; x < w; ++x) {
            float nb[4];
            table.finest_neighbours(x, y, nb);
            const std::int64_t at[4][2] = {{x + 1, y}, {x - 1, y}, {x, y + 1}, {x, y - 1}};
            for (int k = 0; k < 4; ++k) {
                const std::int64_t nx = at[k][0], ny = at[k][1];
                const bool inside = nx >= 0 && ny >= 0 && nx < w && ny < w;
                const float want = inside ? table.height(0, nx, ny) : kEmptyHeight;
                ASSERT_EQ(nb[k], want) << x << ", " << y << ", neighbour " << k;
                read += inside && want == static_cast<float>(nx * 100 + ny) ? 1 : 0;
            }
        }
    }
    // The heights are the cells' own: every neighbour inside the window was read.
    EXPECT_EQ(read, static_cast<int>(4 * w * w - 4 * w));
}

/// The same double, bit for bit (0.0 and -0.0 differ).
bool same_bits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

/// The finest cells along `r` in order (trace_reference's walk, view_renderer.cpp, with the same
/// arithmetic: cell_exits and column_hit), for a table without height stacks.
bool walk_finest_cells(const detail::LevelTable& table, const detail::GridRay& r,
                       detail::GridHit& hit) {
    std::int64_t cx = r.gx, cy = r.gy;
    double t = r.t_min;
    int entered = r.entered;
    for (;;) {
        double tx = 0, ty = 0;
        detail::cell_exits(r, cx, cy, 0, tx, ty);
        const double t_out = std::min(tx, ty);
        const double t_end = std::min(t_out, r.t_max);
        const float h = table.height(0, cx, cy);
        if (detail::column_hit(r, t, t_end, h)) {
            hit = {};
            hit.x = cx;
            hit.y = cy;
            hit.t_in = t;
            hit.t_out = t_end;
            hit.entered_axis = entered;
            hit.h = h;
            return true;
        }
        if (t_out >= r.t_max) {
            return false;
        }
        t = t_out;
        const bool step_x = tx <= ty, step_y = ty <= tx;
        cx += step_x ? r.sx : 0;
        cy += step_y ? r.sy : 0;
        entered = step_x ? 0 : 1;
        if (cx < 0 || cy < 0 || cx >= table.cells(0) || cy >= table.cells(0)) {
            return false;
        }
    }
}

/// Rays over `grid` in every octant from heights around its terrain's, from their origin's cell
/// at the sections' coarsest level (as RaySetup sets up a ray that starts inside the window).
std::vector<detail::GridRay> rays_in_every_octant(const SectionGrid& grid, std::mt19937& rng,
                                                  int count) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto w = static_cast<double>(grid.window_cells());
    std::vector<detail::GridRay> rays;
    for (int i = 0; i < count; ++i) {
        detail::GridRay r;
        r.ox = w * u(rng);
        r.oy = w * u(rng);
        r.oz = 6.0 + 10.0 * u(rng);
        // Level rays and rays along an axis among them (every eighth: dx or dy zero).
        const double ax = i % 16 == 3 ? 0.0 : u(rng) - 0.5, ay = i % 16 == 11 ? 0.0 : u(rng) - 0.5;
        const Vec3d d = normalize(Vec3d{ax, ay, i % 8 == 5 ? 0.0 : -0.2 * u(rng)});
        r.dx = d.x;
        r.dy = d.y;
        r.dz = d.z;
        r.inv_dx = r.dx == 0 ? detail::kInf : 1.0 / r.dx;
        r.inv_dy = r.dy == 0 ? detail::kInf : 1.0 / r.dy;
        r.sx = r.dx < 0 ? -1 : 1;
        r.sy = r.dy < 0 ? -1 : 1;
        r.gx = static_cast<std::int64_t>(r.ox);
        r.gy = static_cast<std::int64_t>(r.oy);
        r.t_max = 4.0 * w;
        rays.push_back(r);
    }
    return rays;
}

TEST(ViewLanes, EveryBatchOfRaysInLanesHitsWhereTheFinestWalkDoes) {
    if (detail::widest_lanes() < 4) {
        BEAMTRACE_SKIP_HARDWARE("no AVX2 on this CPU");
    }
    // 2 x 2 sections of 16 cells over 3 levels (a pyramid level above them), terrain with holes.
    const HeightFieldConfig c = small_window(1.0, 16);
    SectionGrid grid(c, {0, 0, 0});
    test::fill_grid(grid, [](std::int64_t x, std::int64_t y) {
        const auto fx = static_cast<double>(x), fy = static_cast<double>(y);
        return (x * 7 + y * 3) % 11 == 0 ? std::nan("") : 4.0 + 3.0 * std::sin(0.3 * fx + 0.2 * fy);
    });
    const detail::LevelTable table(grid);
    std::mt19937 rng(21);
    const std::vector<detail::GridRay> rays = rays_in_every_octant(grid, rng, 3000);
    std::vector<detail::GridHit> want(rays.size());
    std::vector<std::uint8_t> want_found(rays.size());
    int hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        want_found[i] = walk_finest_cells(table, rays[i], want[i]) ? 1 : 0;
        hits += want_found[i];
    }
    // Both outcomes, many of each (the misses leave the window through each of its sides).
    ASSERT_GT(hits, 600);
    ASSERT_LT(hits, 2400);
    // Batches of every size up to 19 rays (lanes left without a ray in either half of the
    // AVX2 kernel's registers), then all of them; the AVX-512 kernel too where the CPU has it.
    for (const int lanes : {4, 8}) {
        if (detail::widest_lanes() < lanes) {
            continue;
        }
        std::size_t first = 0;
        for (std::size_t size = 0; first < rays.size(); ++size) {
            const std::size_t n = size < 20 ? std::min(size, rays.size() - first) : rays.size();
            const std::size_t from = size < 20 ? first : 0;
            std::vector<detail::GridHit> got(n);
            std::vector<std::uint8_t> found(n, 7);
            ASSERT_EQ(detail::trace_rays_lanes(lanes, table, rays.data() + from, n, got.data(),
                                               found.data()),
                      lanes);
            for (std::size_t k = 0; k < n; ++k) {
                const std::size_t i = from + k;
                ASSERT_EQ(found[k], want_found[i]) << lanes << " lanes, ray " << i;
                if (found[k] == 0) {
                    continue;
                }
                EXPECT_EQ(got[k].x, want[i].x) << i;
                EXPECT_EQ(got[k].y, want[i].y) << i;
                EXPECT_TRUE(same_bits(got[k].t_in, want[i].t_in)) << i;
                EXPECT_TRUE(same_bits(got[k].t_out, want[i].t_out)) << i;
                EXPECT_EQ(got[k].entered_axis, want[i].entered_axis) << i;
                EXPECT_EQ(got[k].h, want[i].h) << i;
            }
            first = size < 20 ? first + n : rays.size();
        }
    }
}

TEST(ViewLanes, ExactDivisorIsTheQuotientBitForBit) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-1074, 1023);
    int products = 0;
    for (const double d : {2.0, 0.5, 1.0, 4.0, 0.25, 1024.0, 3.0, 0.2, 10.0, 1e-3, 6.0}) {
        const detail::ExactDivisor div(d);
        products += div.is_product() ? 1 : 0;
        for (int i = 0; i < 20000; ++i) {
            // Quotients of every size: subnormal, normal, overflowing; zeros of both signs.
            const double x = i < 4 ? (i < 2 ? 0.0 : -0.0) * (i % 2 == 0 ? 1.0 : 1e-300)
                                   : std::ldexp(unit(rng), exponent(rng));
            ASSERT_TRUE(same_bits(div(x), x / d)) << x << " / " << d;
        }
    }
    // The powers of two are products (a division where the divisor would round its inverse).
    EXPECT_EQ(products, 6);
}

/// Compares start_rays_lanes with start_ray_at on the rays of `row` (ray_setup_lanes' `n` rays of
/// a row of pixels) at distances that leave the rays' starts, move them on (to a cell's exit
/// exactly, where the walk's comparisons decide) and end them; returns the rays that moved.
int expect_jump_like_scalar(const detail::RaySetup& setup, const detail::RowDirections& row, int n,
                            int lanes, std::int64_t cells) {
    std::vector<detail::GridRay> rays(static_cast<std::size_t>(n));
    std::vector<double> ts;
    for (int k = 0; k < n; ++k) {
        detail::GridRay& r = rays[static_cast<std::size_t>(k)];
        r.dx = row.dx[k];
        r.dy = row.dy[k];
        r.dz = row.dz[k];
        r.inv_dx = row.inv_dx[k];
        r.inv_dy = row.inv_dy[k];
        if ((row.enter & (1 << k)) == 0 || !setup.clip(r, row.inv_dz[k])) {
            continue;
        }
        double tx = 0, ty = 0;
        detail::cell_exits(r, r.gx, r.gy, 0, tx, ty);
        for (const double t : {r.t_min, 0.5 * (r.t_min + r.t_max), r.t_max, tx, ty,
                               r.t_min + 0.9 * (r.t_max - r.t_min)}) {
            if (std::isfinite(t) && ts.size() < 12) {
                ts.push_back(t);
            }
        }
    }
    int moved = 0;
    for (const double t : ts) {
        detail::RowDirections lanes_row = row;
        const int go_on = detail::start_rays_lanes(lanes, setup.clip_frame(), t, cells, lanes_row);
        for (int k = 0; k < n; ++k) {
            if ((row.enter & (1 << k)) == 0) {
                EXPECT_EQ(go_on & (1 << k), 0);
                continue;
            }
            detail::GridRay r = rays[static_cast<std::size_t>(k)];
            const bool scalar = detail::start_ray_at(r, t, cells);
            EXPECT_EQ((go_on & (1 << k)) != 0, scalar) << "ray " << k << " at " << t;
            if (!scalar) {
                continue;
            }
            moved += r.entered >= 0 ? 1 : 0;
            EXPECT_TRUE(same_bits(lanes_row.t_min[k], r.t_min))
                << lanes_row.t_min[k] << " " << r.t_min;
            EXPECT_EQ(static_cast<std::int64_t>(lanes_row.gx[k]), r.gx);
            EXPECT_EQ(static_cast<std::int64_t>(lanes_row.gy[k]), r.gy);
            EXPECT_EQ(static_cast<int>(lanes_row.entered[k]), r.entered);
        }
    }
    return moved;
}

/// Compares ray_setup_lanes with RaySetup::operator() on every pixel of `camera` (rows of
/// kRowDirections pixels and a shorter last one), and start_rays_lanes with start_ray_at on
/// them (expect_jump_like_scalar; `jumped` counts the rays moved); returns the rays that enter.
int expect_setup_like_scalar(const SectionGrid& grid, const ViewCamera& camera, int lanes,
                             int& jumped) {
    const CameraRays rays(camera);
    const detail::RaySetup setup(grid, camera.position);
    const detail::DirectionFrame frame{
        rays.forward().x, rays.forward().y, rays.forward().z, rays.right().x, rays.right().y,
        rays.right().z,   rays.up().x,      rays.up().y,      rays.up().z,    setup.per_cell()};
    std::vector<double> u;
    for (int px = 0; px < camera.width; ++px) {
        u.push_back(rays.u(px));
    }
    int entered = 0;
    for (int py = 0; py < camera.height; ++py) {
        for (int x0 = 0; x0 < camera.width; x0 += detail::kRowDirections) {
            const int n = std::min(detail::kRowDirections, camera.width - x0);
            detail::RowDirections out;
            detail::ray_setup_lanes(lanes, frame, setup.clip_frame(), u.data() + x0, rays.v(py), n,
                                    out);
            for (int k = 0; k < n; ++k) {
                detail::GridRay r;
                const bool enters = setup(rays.direction_at(u[x0 + k], rays.v(py)), r);
                const bool lane = (out.enter & (1 << k)) != 0;
                EXPECT_EQ(lane, enters) << "pixel " << x0 + k << ", " << py;
                if (!enters || !lane) {
                    continue;
                }
                ++entered;
                EXPECT_TRUE(same_bits(out.dx[k], r.dx) && same_bits(out.dy[k], r.dy) &&
                            same_bits(out.dz[k], r.dz) && same_bits(out.inv_dx[k], r.inv_dx) &&
                            same_bits(out.inv_dy[k], r.inv_dy))
                    << "pixel " << x0 + k << ", " << py;
                EXPECT_TRUE(same_bits(out.t_min[k], r.t_min)) << out.t_min[k] << " " << r.t_min;
                EXPECT_TRUE(same_bits(out.t_max[k], r.t_max)) << out.t_max[k] << " " << r.t_max;
                EXPECT_EQ(static_cast<std::int64_t>(out.gx[k]), r.gx);
                EXPECT_EQ(static_cast<std::int64_t>(out.gy[k]), r.gy);
            }
            if (::testing::Test::HasFailure()) {
                return entered;
            }
            jumped += expect_jump_like_scalar(setup, out, n, lanes, grid.window_cells());
        }
    }
    return entered;
}

TEST(ViewLanes, RaySetupInLanesIsTheScalarSetupBitForBit) {
    if (detail::widest_lanes() < 4) {
        BEAMTRACE_SKIP_HARDWARE("no AVX2 on this CPU");
    }
    const HeightFieldConfig c = small_window(0.5, 4);
    SectionGrid grid(c, {0, 0, 0});
    test::fill_grid(grid, [](std::int64_t x, std::int64_t y) {
        return 1.0 + 0.25 * static_cast<double>((x * 7 + y * 3) % 5);
    });
    const double w = static_cast<double>(grid.window_cells()) * c.cell_size;
    const Vec3d corner = grid.window_corner();
    std::mt19937 rng(21);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int entered = 0, cameras = 0, jumped = 0;
    for (int i = 0; i < 120; ++i) {
        ViewCamera cam;
        // Inside and outside the window, below, within and above the heights; level rays
        // (pitch 0), rays along the axes (yaw a multiple of 90 degrees, odd sizes: a centre
        // column and row) and straight-down ones.
        cam.position = {corner.x + (1.4 * unit(rng) - 0.2) * w,
                        corner.y + (1.4 * unit(rng) - 0.2) * w, corner.z + 4.0 * unit(rng) - 0.5};
        cam.yaw_deg = i % 3 == 0 ? 90.0 * (i % 4) : 360.0 * unit(rng);
        cam.pitch_deg = i % 5 == 0 ? 0.0 : i % 7 == 0 ? -89.0 : 120.0 * unit(rng) - 80.0;
        cam.hfov_deg = 20.0 + 100.0 * unit(rng);
        cam.width = 13 + (i % 4);
        cam.height = 9 + (i % 3);
        ++cameras;
        for (const int lanes : {4, 8}) {
            if (lanes > detail::widest_lanes()) {
                continue;
            }
            entered += expect_setup_like_scalar(grid, cam, lanes, jumped);
            ASSERT_FALSE(::testing::Test::HasFailure()) << "camera " << i << ", " << lanes;
        }
    }
    // Most cameras see the heights; many rays move on to a later cell.
    EXPECT_GT(entered, cameras * 20);
    EXPECT_GT(jumped, entered);
    std::printf("[ jumps    ] %d rays entered, %d moved on\n", entered, jumped);
}

TEST(ViewLanes, JumpInLanesThroughACornerEntersThroughXAsTheScalarJump) {
    // Diagonal rays from a cell's centre cross both borders at once at every corner: the walk
    // steps in x and y and reports the x face.
    detail::ClipFrame clip;
    clip.ox = 8.5;
    clip.oy = 8.5;
    detail::RowDirections row{};
    for (int k = 0; k < detail::kRowDirections; ++k) {
        const double d = k % 2 == 0 ? 0.5 + 0.1 * k : -(0.5 + 0.1 * k);
        row.dx[k] = row.dy[k] = d;
        row.inv_dx[k] = row.inv_dy[k] = 1.0 / d;
        row.dz[k] = -0.5;
        row.t_min[k] = 0.0;
        row.t_max[k] = 100.0;
        row.gx[k] = row.gy[k] = 8.0;
    }
    row.enter = (1 << detail::kRowDirections) - 1;
    for (const int lanes : {4, 8}) {
        if (lanes > detail::widest_lanes()) {
            continue;
        }
        for (const double t : {2.0, 3.3, 5.0}) {
            detail::RowDirections out = row;
            const int go_on = detail::start_rays_lanes(lanes, clip, t, 16, out);
            for (int k = 0; k < detail::kRowDirections; ++k) {
                detail::GridRay r;
                detail::lane_ray(clip, row, k, r);
                ASSERT_TRUE(detail::start_ray_at(r, t, 16));
                ASSERT_NE(go_on & (1 << k), 0) << k;
                ASSERT_NE(r.gx, 8) << k << " at " << t;
                EXPECT_EQ(r.entered, 0);
                EXPECT_EQ(static_cast<int>(out.entered[k]), r.entered) << k << " at " << t;
                EXPECT_EQ(static_cast<std::int64_t>(out.gx[k]), r.gx);
                EXPECT_EQ(static_cast<std::int64_t>(out.gy[k]), r.gy);
                EXPECT_TRUE(same_bits(out.t_min[k], r.t_min));
            }
        }
    }
}

/// Hits for the shading test: cells of `grid` that hold a height, rays going down, up and level,
/// every face, spans that start on, before and past the top's plane.
std::vector<std::pair<detail::GridRay, detail::GridHit>> shading_hits(const SectionGrid& grid,
                                                                      std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const std::int64_t w = grid.window_cells();
    std::vector<std::pair<detail::GridRay, detail::GridHit>> out;
    while (out.size() < 3000) {
        detail::GridHit hit;
        hit.x = static_cast<std::int64_t>(u(rng) * static_cast<double>(w));
        hit.y = static_cast<std::int64_t>(u(rng) * static_cast<double>(w));
        hit.h = grid.height(0, hit.x, hit.y);
        if (hit.h == kEmptyHeight) {
            continue;
        }
        detail::GridRay r;
        // One origin height (the camera's) for every 8 hits.
        r.oz = out.size() % 8 == 0 ? 40.0 * u(rng) - 5.0 : out.back().first.oz;
        const int kind = static_cast<int>(out.size() % 5);
        r.dz = kind == 4 ? 0.0 : (kind == 3 ? 1.0 : -1.0) * (0.05 + u(rng));
        r.sx = u(rng) < 0.5 ? -1 : 1;
        r.sy = u(rng) < 0.5 ? -1 : 1;
        hit.entered_axis = static_cast<int>(3.0 * u(rng)) - 1;
        const double t_top = (static_cast<double>(hit.h) - r.oz) / r.dz;
        // On the top's plane, just before it, or anywhere.
        hit.t_in = kind == 0 && t_top > 0 ? t_top : (kind == 1 ? t_top - u(rng) : 60.0 * u(rng));
        hit.t_in = std::max(hit.t_in, 0.0);
        hit.t_out = hit.t_in + (kind == 2 ? 0.0 : 2.0 * u(rng));
        out.emplace_back(r, hit);
    }
    return out;
}

/// shade_lanes against shade_hit, bit for bit, on every hit of shading_hits.
void expect_shading_like_scalar(const SectionGrid& grid, const RenderOptions& options, int lanes,
                                std::mt19937& rng) {
    const detail::LevelTable table(grid);
    const detail::ExactDivisor per_two(2.0 * grid.config().cell_size);
    const auto hits = shading_hits(grid, rng);
    const auto batch = std::make_unique<detail::ShadeBatch>();
    const auto n = static_cast<std::size_t>(lanes);
    for (std::size_t first = 0; first + n <= hits.size(); first += n) {
        // The lanes' hits share their origin's height (shading_hits: 8 hits a height).
        const detail::ShadeFrame frame = detail::shade_frame(grid, options, hits[first].first.oz);
        for (std::size_t j = 0; j < n; ++j) {
            detail::gather_shade(grid, table, options.shading, hits[first + j].first,
                                 hits[first + j].second, *batch, static_cast<int>(j));
        }
        detail::shade_lanes(lanes, frame, *batch, lanes);
        for (std::size_t j = 0; j < n; ++j) {
            std::uint8_t rgb[3];
            float depth = 0;
            detail::shade_hit(
                grid,
                [&](std::int64_t x, std::int64_t y, float* nb) {
                    table.finest_neighbours(x, y, nb);
                },
                per_two, hits[first + j].first, hits[first + j].second, options, rgb, depth);
            ASSERT_EQ(std::memcmp(&depth, batch->depth + j, sizeof depth), 0) << first + j;
            for (std::size_t c = 0; c < 3; ++c) {
                ASSERT_EQ(static_cast<int>(rgb[c]), batch->rgb[c][j]) << first + j << ", " << c;
            }
        }
    }
}

TEST(ViewLanes, ShadingInLanesIsShadeHitBitForBit) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int ran = 0;
    for (const int lanes : {4, 8}) {
        if (detail::widest_lanes() < lanes) {
            continue;
        }
        // 1 ft cells divide by a product, 0.3 ft cells by a division; rgb and height colours.
        for (const double cell : {1.0, 0.3}) {
            HeightFieldConfig c = small_window(cell, 4);
            c.color = cell == 1.0 ? ColorMode::rgb : ColorMode::height;
            SectionGrid grid(c, {0, 0, 0});
            // Steps and slopes, a tenth of the cells empty (their neighbours shade with their
            // own height).
            test::fill_grid(grid, [&](std::int64_t x, std::int64_t y) {
                return u(rng) < 0.1 ? std::nan("")
                                    : 0.7 * static_cast<double>(x) - 0.3 * static_cast<double>(y) +
                                          (u(rng) < 0.3 ? 4.0 * u(rng) : 0.0);
            });
            for (const bool shading : {true, false}) {
                for (const double fog : {0.0, 25.0}) {
                    RenderOptions options;
                    options.shading = shading;
                    options.fog_distance = fog;
                    options.sky = {200, 100, 250};
                    expect_shading_like_scalar(grid, options, lanes, rng);
                    ++ran;
                }
            }
        }
    }
    if (ran == 0) {
        BEAMTRACE_SKIP_HARDWARE("no AVX2 on this CPU");
    }
}

}  // namespace
}  // namespace beamtrace
