// Beams of the view renderer (src/heightfield/detail/view_beam.hpp): the start distance of an
// 8 x 8 block of rays never passes a column any of them meets (checked against a brute-force
// ray-box test of every column), the jump of a ray's walk to a distance lands in the cell, at the
// distance and through the face the cell-by-cell walk reaches, and images rendered with beams
// equal the brute-force reference bit for bit from cameras above, inside and below the terrain.
#include "heightfield/detail/view_beam.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/heightfield/view_renderer.hpp"
#include "heightfield/heightfield_test_support.hpp"

namespace beamtrace {
namespace {

using detail::GridRay;
using detail::kInf;

/// 2 x 2 sections of 16 x 16 cells of 1 m (levels 3, coarse 4): a 32-cell window.
HeightFieldConfig beam_config() {
    HeightFieldConfig c;
    c.cell_size = 1.0;
    c.levels = 3;
    c.section_cells = 4;
    c.sections = 2;
    return c;
}

/// Hills from 0 to about 10 m with 15 % empty cells and a few tall spikes.
void fill_random_terrain(SectionGrid& grid, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    test::fill_grid(grid, [&](std::int64_t x, std::int64_t y) {
        const double v = u(rng);
        if (v < 0.15) {
            return std::nan("");
        }
        const double spike = v > 0.98 ? 6.0 : 0.0;
        return 3.0 +
               3.0 * std::sin(0.3 * static_cast<double>(x)) *
                   std::cos(0.2 * static_cast<double>(y)) +
               2.0 * v + spike;
    });
}

ViewCamera camera(Vec3d p, double yaw, double pitch, int w, int h) {
    ViewCamera c;
    c.position = p;
    c.yaw_deg = yaw;
    c.pitch_deg = pitch;
    c.hfov_deg = 60;
    c.width = w;
    c.height = h;
    return c;
}

/// Random cameras: above, inside and below the terrain, anywhere in and around the window,
/// every yaw; a third of them at grazing pitches (within 2 degrees of level).
std::vector<ViewCamera> random_cameras(int count, int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<ViewCamera> cams;
    for (int i = 0; i < count; ++i) {
        const Vec3d p{-8.0 + 48.0 * u(rng), -8.0 + 48.0 * u(rng), -3.0 + 25.0 * u(rng)};
        const double pitch = i % 3 == 0 ? -2.0 + 4.0 * u(rng) : -89.0 + 178.0 * u(rng);
        cams.push_back(camera(p, 360.0 * u(rng), pitch, w, h));
    }
    return cams;
}

/// The first distance in [t_min, t_max] at which the ray is inside a column of the grid (the
/// box of a non-empty finest cell from its height down forever), by a ray-box test of every
/// column: kInf when there is none.
double first_contact(const SectionGrid& grid, const GridRay& r) {
    const std::int64_t cells = grid.window_cells();
    const auto slab = [](double o, double d, double lo, double hi, double& t0, double& t1) {
        if (d == 0) {
            if (!(o >= lo && o < hi)) {
                t0 = kInf;
            }
            return;
        }
        const double a = (lo - o) / d, b = (hi - o) / d;
        t0 = std::max(t0, std::min(a, b));
        t1 = std::min(t1, std::max(a, b));
    };
    double best = kInf;
    for (std::int64_t y = 0; y < cells; ++y) {
        for (std::int64_t x = 0; x < cells; ++x) {
            const float h = grid.height(0, x, y);
            if (h == kEmptyHeight) {
                continue;
            }
            double t0 = r.t_min, t1 = r.t_max;
            slab(r.ox, r.dx, static_cast<double>(x), static_cast<double>(x + 1), t0, t1);
            slab(r.oy, r.dy, static_cast<double>(y), static_cast<double>(y + 1), t0, t1);
            slab(r.oz, r.dz, -kInf, static_cast<double>(h), t0, t1);
            if (t0 <= t1) {
                best = std::min(best, t0);
            }
        }
    }
    return best;
}

TEST(ViewBeam, StartDistanceNeverPassesAColumnAnyRayOfTheBeamMeets) {
    SectionGrid grid(beam_config(), {0, 0, 0});
    fill_random_terrain(grid, 11);
    const detail::LevelTable table(grid);
    int beams = 0, moved = 0, empty = 0;
    for (const ViewCamera& cam : random_cameras(150, 32, 24, 5)) {
        const CameraRays rays(cam);
        const detail::RaySetup setup(grid, cam.position);
        for (int by = 0; by < cam.height; by += detail::kBeamPixels) {
            for (int bx = 0; bx < cam.width; bx += detail::kBeamPixels) {
                std::vector<GridRay> block;
                detail::Beam beam;
                for (int py = by; py < by + detail::kBeamPixels; ++py) {
                    for (int px = bx; px < bx + detail::kBeamPixels; ++px) {
                        GridRay r;
                        if (setup(rays.direction(px, py), r)) {
                            beam.add(r);
                            block.push_back(r);
                        }
                    }
                }
                if (block.empty()) {
                    continue;
                }
                const double start = detail::beam_start(table, beam).t;
                ++beams;
                moved += start > beam.t_lo ? 1 : 0;
                empty += start == kInf ? 1 : 0;
                for (const GridRay& r : block) {
                    const double first = first_contact(grid, r);
                    ASSERT_LE(start, first)
                        << "camera " << cam.position.x << "," << cam.position.y << ","
                        << cam.position.z << " yaw " << cam.yaw_deg << " pitch " << cam.pitch_deg
                        << ", beam at pixel " << bx << "," << by;
                }
            }
        }
    }
    // Not vacuous: most beams start past their rays' entry into the heights' box, some see
    // nothing at all.
    std::printf("[ beams    ] %d beams, %d moved on, %d empty\n", beams, moved, empty);
    EXPECT_GT(moved, beams / 3);
    EXPECT_GT(empty, 0);
}

/// The cell-by-cell walk of the reference renderer (trace_reference) from the ray's start up to
/// the cell it is in at distance t, ignoring heights: false when the ray ends by t.
bool walk_to(const SectionGrid& grid, GridRay r, double t, GridRay& out) {
    out = r;
    if (!(t > r.t_min)) {
        return true;  // not yet started: the start
    }
    if (t >= r.t_max) {
        return false;  // every span the walk tests ends by t_max <= t
    }
    std::int64_t cx = r.gx, cy = r.gy;
    double at = r.t_min;
    int entered = -1;
    for (;;) {
        double tx, ty;
        detail::cell_exits(r, cx, cy, 0, tx, ty);
        const double t_out = std::min(tx, ty);
        if (t_out > t) {
            break;
        }
        if (t_out >= r.t_max) {
            return false;
        }
        at = t_out;
        const bool step_x = tx <= ty;
        const bool step_y = ty <= tx;
        cx += step_x ? r.sx : 0;
        cy += step_y ? r.sy : 0;
        entered = step_x ? 0 : 1;
        if (cx < 0 || cy < 0 || cx >= grid.window_cells() || cy >= grid.window_cells()) {
            return false;
        }
    }
    out = r;
    out.gx = cx;
    out.gy = cy;
    out.t_min = at;
    out.entered = entered;
    return true;
}

TEST(ViewBeam, JumpLandsWhereTheCellWalkIsAtThatDistance) {
    SectionGrid grid(beam_config(), {0, 0, 0});
    fill_random_terrain(grid, 3);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int checked = 0, ties = 0;
    for (int i = 0; i < 20000; ++i) {
        // Half the rays on the diagonals from a cell's corner, where the walk steps through both
        // faces at once; some along the axes and straight down.
        const bool diagonal = i % 2 == 0;
        const double ax = diagonal ? std::floor(40.0 * u(rng)) - 4.0 : -4.0 + 40.0 * u(rng);
        const double ay = diagonal ? std::floor(40.0 * u(rng)) - 4.0 : -4.0 + 40.0 * u(rng);
        const Vec3d p{ax, ay, -3.0 + 20.0 * u(rng)};
        const double sx = u(rng) < 0.5 ? -1.0 : 1.0, sy = u(rng) < 0.5 ? -1.0 : 1.0;
        const double dz = -2.0 + 4.0 * u(rng);
        Vec3d dir = diagonal ? Vec3d{sx, sy, dz} : Vec3d{sx * u(rng), sy * u(rng), dz};
        if (i % 16 == 1) {
            dir = {0.0, sy, dz};
        } else if (i % 16 == 3) {
            dir = {sx, 0.0, dz};
        } else if (i % 64 == 5) {
            dir = {0.0, 0.0, -1.0};
        }
        GridRay r;
        if (!detail::RaySetup(grid, p)(normalize(dir), r)) {
            continue;
        }
        const double t = r.t_min + (r.t_max - r.t_min) * 1.1 * u(rng);
        GridRay expected;
        const bool reaches = walk_to(grid, r, t, expected);
        GridRay moved = r;
        ASSERT_EQ(detail::start_ray_at(moved, t, grid.window_cells()), reaches)
            << i << " t " << t << " [" << r.t_min << ", " << r.t_max << "] o " << r.ox << ","
            << r.oy << "," << r.oz << " d " << r.dx << "," << r.dy << "," << r.dz << " g " << r.gx
            << "," << r.gy << " -> " << moved.gx << "," << moved.gy;
        if (!reaches) {
            continue;
        }
        ++checked;
        // Entered through x at the distance of its y face as well: both at once.
        const double y_face = static_cast<double>(r.sy > 0 ? moved.gy : moved.gy + 1);
        ties += moved.entered == 0 && moved.gy != r.gy && moved.t_min == (y_face - r.oy) * r.inv_dy
                    ? 1
                    : 0;
        ASSERT_EQ(moved.gx, expected.gx) << i;
        ASSERT_EQ(moved.gy, expected.gy) << i;
        ASSERT_EQ(moved.t_min, expected.t_min) << i;  // the same double, not a close one
        ASSERT_EQ(moved.entered, expected.entered) << i;
    }
    std::printf("[ jumps    ] %d checked, %d through both faces at once\n", checked, ties);
    EXPECT_GT(checked, 10000);
    EXPECT_GT(ties, 100);
}

/// Images with beams (render_view, every kernel this CPU has) equal the reference bit for bit,
/// colour and depth, from random cameras above, inside and below random terrain.
TEST(ViewBeam, ImagesEqualTheReferenceFromCamerasAboveInsideAndBelowTheTerrain) {
    SectionGrid grid(beam_config(), {0, 0, 0});
    fill_random_terrain(grid, 21);
    ThreadPool pool(2);
    RenderOptions options;
    options.fog_distance = 40.0;
    int compared = 0;
    for (const ViewCamera& cam : random_cameras(60, 48, 40, 17)) {
        const ViewImage slow = render_view_reference(grid, cam, options, pool);
        for (const int lanes : {1, 4, 8}) {
            RenderOptions fast_options = options;
            fast_options.simd_lanes = lanes;
            fast_options.tile_pixels = lanes == 4 ? 12 : 16;  // beams cut at tile edges too
            const ViewImage fast = render_view(grid, cam, fast_options, pool);
            ASSERT_EQ(fast.rgb, slow.rgb)
                << "lanes " << lanes << " camera " << cam.position.x << "," << cam.position.y << ","
                << cam.position.z << " yaw " << cam.yaw_deg << " pitch " << cam.pitch_deg;
            ASSERT_EQ(fast.depth, slow.depth) << "lanes " << lanes;
            ++compared;
        }
    }
    EXPECT_EQ(compared, 180);
}

}  // namespace
}  // namespace beamtrace
