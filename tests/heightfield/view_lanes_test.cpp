// The SIMD lanes of the view traversal round like the scalar walk: rays built to touch a flat
// terrain's top within a rounding error at the end of their first cell, where a fused
// multiply-add (oz + dz * t in one rounding) and the scalar walk's two roundings decide the hit
// differently. The AVX-512 kernel (compiled for a target that has FMA) must agree with the AVX2
// one (which has none) on every ray.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "heightfield/detail/view_trace_simd.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(ViewLanes, Avx512KernelRoundsLikeTheScalarWalkWhereARayTouchesATop) {
    if (detail::widest_lanes() < 8) {
        BEAMTRACE_SKIP_HARDWARE("no AVX-512 on this CPU");
    }
    HeightFieldConfig c;
    c.cell_size = 1.0;
    c.levels = 3;
    c.section_cells = 4;
    c.sections = 2;
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

}  // namespace
}  // namespace beamtrace
