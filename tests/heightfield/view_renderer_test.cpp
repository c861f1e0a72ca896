#include "beamtrace/heightfield/view_renderer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/heightfield/view_session.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// 2 x 2 sections of 16 x 16 cells (levels 3, coarse 4) of 1 m, origin at 0.
HeightFieldConfig small_config() {
    HeightFieldConfig c;
    c.cell_size = 1.0;
    c.levels = 3;
    c.section_cells = 4;
    c.sections = 2;
    return c;
}

ViewCamera camera_at(Vec3d p, double yaw, double pitch, int w = 64, int h = 48) {
    ViewCamera c;
    c.position = p;
    c.yaw_deg = yaw;
    c.pitch_deg = pitch;
    c.hfov_deg = 60;
    c.width = w;
    c.height = h;
    return c;
}

TEST(ViewRenderer, FlatPlateauSeenStraightDownHasTheExpectedDepthAndColour) {
    SectionGrid grid(small_config(), {0, 0, 0});
    test::fill_grid(grid, [](std::int64_t x, std::int64_t y) {
        return x >= 8 && x < 24 && y >= 8 && y < 24 ? 10.0 : std::nan("");
    });
    ASSERT_EQ(grid.loaded_sections(), 4);
    ThreadPool pool(2);
    RenderOptions options;
    options.shading = false;
    const ViewCamera cam = camera_at({16.5, 16.5, 50.0}, 0.0, -90.0, 41, 41);
    const ViewImage img = render_view(grid, cam, options, pool);
    const std::size_t centre = 20 * 41 + 20;
    EXPECT_FLOAT_EQ(img.depth[centre], 40.0f);
    // One height only: the middle of the ramp (yellow).
    EXPECT_EQ(img.rgb[3 * centre], 255);
    EXPECT_EQ(img.rgb[3 * centre + 1], 255);
    EXPECT_EQ(img.rgb[3 * centre + 2], 0);
    // Corners look past the plateau over empty cells: sky, no depth.
    EXPECT_TRUE(std::isinf(img.depth[0]));
    EXPECT_EQ(img.rgb[0], options.sky[0]);
    // Every hit is on the plateau top: depth = 40 / cos(angle off the axis).
    for (std::size_t i = 0; i < img.depth.size(); ++i) {
        if (std::isfinite(img.depth[i])) {
            const Vec3d d =
                CameraRays(cam).direction(static_cast<int>(i % 41), static_cast<int>(i / 41));
            EXPECT_NEAR(img.depth[i], 40.0 / -d.z, 1e-3) << i;
        }
    }
}

TEST(ViewRenderer, ShadedFoggedPlateauHasTheColourOfItsFormulaInEveryChannel) {
    // The plateau of the test above with shading and fog: a flat top (normal straight up, lit by
    // 0.35 + 0.65 * the sun's height), faded to the sky by 1 - exp(-distance / fog) per channel.
    SectionGrid grid(small_config(), {0, 0, 0});
    test::fill_grid(grid, [](std::int64_t x, std::int64_t y) {
        return x >= 8 && x < 24 && y >= 8 && y < 24 ? 10.0 : std::nan("");
    });
    ThreadPool pool(2);
    RenderOptions options;
    options.fog_distance = 30.0;
    options.sky = {150, 180, 220};
    const ViewCamera cam = camera_at({16.5, 16.5, 50.0}, 0.0, -90.0, 41, 41);
    const ViewImage img = render_view(grid, cam, options, pool);
    const double sun_z = 1.0 / std::sqrt(0.4 * 0.4 + 0.5 * 0.5 + 1.0);
    const double light = 0.35 + 0.65 * sun_z;
    const double base[3] = {255.0, 255.0, 0.0};  // one height: the middle of the ramp
    int hits = 0;
    for (std::size_t i = 0; i < img.depth.size(); ++i) {
        if (!std::isfinite(img.depth[i])) {
            continue;
        }
        ++hits;
        const Vec3d d =
            CameraRays(cam).direction(static_cast<int>(i % 41), static_cast<int>(i / 41));
        const double f = 1.0 - std::exp(-(40.0 / -d.z) / options.fog_distance);
        for (std::size_t k = 0; k < 3; ++k) {
            const double c = base[k] * light * (1.0 - f) + static_cast<double>(options.sky[k]) * f;
            EXPECT_NEAR(static_cast<double>(img.rgb[3 * i + k]), std::round(c), 1.0)
                << "pixel " << i << " channel " << k;
        }
    }
    EXPECT_GT(hits, 100);
}

TEST(ViewRenderer, EmptyCellsAreSeeThroughNotZeroHeight) {
    SectionGrid grid(small_config(), {0, 0, 0});
    // A plateau at z = 10 with a hole of empty cells in the middle; one cell at z = 0 is the
    // lowest point (rays end there).
    test::fill_grid(grid, [](std::int64_t x, std::int64_t y) {
        const bool hole = x >= 12 && x < 20 && y >= 12 && y < 20;
        return hole ? std::nan("") : (x == 0 && y == 0 ? 0.0 : 10.0);
    });
    ThreadPool pool(1);
    const ViewCamera cam = camera_at({16.5, 16.5, 50.0}, 0.0, -90.0, 41, 41);
    const ViewImage img = render_view(grid, cam, {}, pool);
    EXPECT_TRUE(std::isinf(img.depth[20 * 41 + 20]));     // through the hole: nothing
    EXPECT_TRUE(std::isfinite(img.depth[10 * 41 + 10]));  // the plateau around it
    // Seen from the side at a low angle the hole's far wall is hit, not a floor at 0.
    const ViewImage side =
        render_view(grid, camera_at({16.5, 16.5, 12.0}, 0.0, -45.0, 1, 1), {}, pool);
    ASSERT_TRUE(std::isfinite(side.depth[0]));
    EXPECT_NEAR(side.depth[0], 3.5 * std::sqrt(2.0), 1e-6);  // the wall at x = 20, z = 8.5
}

/// True when this CPU runs the kernel of `lanes` rays: asked of the CPU directly, not of the
/// renderer, so that a renderer that wrongly thinks the CPU lacks AVX-512 fails rather than skips.
bool cpu_has_kernel(int lanes) {
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    if (lanes == 8) {
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx512cd");
    }
    if (lanes == 4) {
        return __builtin_cpu_supports("avx2");
    }
#endif
    return lanes == 1;
}

const char* kernel_name(int lanes) {
    return lanes == 8 ? "AVX-512 (8 lanes)" : lanes == 4 ? "AVX2 (4 lanes)" : "scalar (1 ray)";
}

/// Random terrain with holes (15 % empty cells) over the grid of `config`, seen from cameras in
/// every octant, up and down and nearly level, inside and outside the window: the hierarchical
/// renderer with the kernel of `lanes` rays equals the brute-force reference, and that kernel
/// is the one that ran (not a narrower fallback).
void expect_random_terrain_matches_reference(const HeightFieldConfig& config, int lanes) {
    SectionGrid grid(config, {0, 0, 0});
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    test::fill_grid(grid, [&](std::int64_t x, std::int64_t y) {
        const double v = u(rng);
        if (v < 0.15) {
            return std::nan("");
        }
        return 3.0 * std::sin(0.3 * static_cast<double>(x)) *
                   std::cos(0.2 * static_cast<double>(y)) +
               4.0 * v;
    });
    ThreadPool pool(2);
    RenderOptions options;
    options.fog_distance = 30.0;
    RenderOptions lane_options = options;
    lane_options.simd_lanes = lanes;
    const double w = static_cast<double>(grid.window_cells());
    for (const double yaw : {20.0, 110.0, 200.0, 290.0, 0.0, 90.0}) {
        for (const double pitch : {-60.0, -15.0, -2.0, 20.0}) {
            for (const Vec3d p : {Vec3d{0.51 * w, 0.49 * w, 9.0}, Vec3d{-5.0, -3.0, 12.0},
                                  Vec3d{1.25 * w, 1.1 * w, 2.0}}) {
                const ViewCamera cam = camera_at(p, yaw, pitch);
                const ViewImage slow = render_view_reference(grid, cam, options, pool);
                const ViewImage fast = render_view(grid, cam, lane_options, pool);
                ASSERT_EQ(fast.kernel_lanes, lanes) << "asked for " << kernel_name(lanes)
                                                    << ", ran " << kernel_name(fast.kernel_lanes);
                std::string first;
                EXPECT_EQ(test::count_mismatches(fast, slow, first), 0u)
                    << kernel_name(lanes) << ", yaw " << yaw << " pitch " << pitch << " at " << p.x
                    << "," << p.y << ": " << first;
            }
        }
    }
    std::printf("[ kernel   ] %s ran\n", kernel_name(lanes));
}

/// One test per kernel (1, 4 and 8 rays), so a CPU without AVX-512 skips the 8-lane test by
/// name instead of passing it on the AVX2 fallback.
class ViewRendererKernel : public ::testing::TestWithParam<int> {
  protected:
    void SetUp() override {
        if (!cpu_has_kernel(GetParam())) {
            BEAMTRACE_SKIP_HARDWARE("no " << (GetParam() == 8 ? "AVX-512" : "AVX2")
                                          << " on this CPU");
        }
    }
};

TEST_P(ViewRendererKernel, MatchesTheBruteForceReferenceOnRandomTerrainInEveryOctant) {
    expect_random_terrain_matches_reference(small_config(), GetParam());
}

TEST_P(ViewRendererKernel, MatchesTheReferenceOnAnOddWindowWithAPaddedPyramid) {
    // 3 x 3 sections of 8 x 8 cells: 24, 12 and 6 cells per side at the sections' levels,
    // then a pyramid of 3 (rows padded to 4), 2 and 1.
    HeightFieldConfig c = small_config();
    c.sections = 3;
    c.section_cells = 2;
    c.levels = 3;
    expect_random_terrain_matches_reference(c, GetParam());
}

/// Test names by instruction set: ViewRenderer/ViewRendererKernel.*/Avx512 and so on.
std::string kernel_test_name(const ::testing::TestParamInfo<int>& param) {
    return param.param == 8 ? "Avx512" : param.param == 4 ? "Avx2" : "Scalar";
}

INSTANTIATE_TEST_SUITE_P(ViewRenderer, ViewRendererKernel, ::testing::Values(1, 4, 8),
                         kernel_test_name);

TEST(ViewRenderer, DefaultLanesRunTheWidestKernelOfThisCpuAndStacksRunOneRayAtATime) {
    const int widest = cpu_has_kernel(8) ? 8 : cpu_has_kernel(4) ? 4 : 1;
    SectionGrid grid(small_config(), {0, 0, 0});
    test::fill_grid(grid, [](std::int64_t x, std::int64_t y) {
        return static_cast<double>((x * 7 + y * 3) % 5);
    });
    ThreadPool pool(2);
    const ViewCamera cam = camera_at({16.0, 16.0, 20.0}, 30.0, -40.0, 32, 24);
    EXPECT_EQ(render_view(grid, cam, {}, pool).kernel_lanes, widest);
    RenderOptions four;
    four.simd_lanes = 4;
    EXPECT_EQ(render_view(grid, cam, four, pool).kernel_lanes, std::min(widest, 4));
    EXPECT_EQ(render_view_reference(grid, cam, {}, pool).kernel_lanes, 1);
    HeightFieldConfig stacked = small_config();
    stacked.height_stacks = 2;
    SectionGrid stacks(stacked, {0, 0, 0});
    test::fill_grid(stacks, [](std::int64_t, std::int64_t) { return 1.0; });
    EXPECT_EQ(render_view(stacks, cam, {}, pool).kernel_lanes, 1);
    std::printf("[ kernel   ] default: %s\n", kernel_name(widest));
}

class ViewAutzen : public ::testing::Test {
  protected:
    void SetUp() override {
        path_ = test::shared_data("las/las/autzen_trim.las");
        BEAMTRACE_REQUIRE_FILE(path_);
        ViewSessionConfig config;
        config.field.cell_size = 2.0;  // feet: about one point per cell
        config.field.levels = 5;
        config.field.section_cells = 8;  // 128 cells = 256 ft per section
        config.field.sections = 4;
        config.threads = 2;
        session_ = std::make_unique<ViewSession>(std::span(&path_, 1), config);
        lo_ = session_->sources().min();
        hi_ = session_->sources().max();
        centre_ = (lo_ + hi_) * 0.5;
        const IngestStats stats = session_->move_to(centre_);
        ASSERT_EQ(stats.points_read, 110000u);
        ASSERT_GT(stats.points_inserted, 50000u);
    }

    void expect_same(const ViewCamera& cam, std::size_t min_hits) {
        RenderOptions options;
        const ViewImage fast = session_->render(cam, options);
        const ViewImage slow =
            render_view_reference(session_->grid(), cam, options, session_->pool());
        EXPECT_GE(fast.hits(), min_hits);
        std::string first;
        EXPECT_EQ(test::count_mismatches(fast, slow, first), 0u) << first;
    }

    std::filesystem::path path_;
    std::unique_ptr<ViewSession> session_;
    Vec3d lo_, hi_, centre_;
};

TEST_F(ViewAutzen, FromAboveEqualsTheReference) {
    expect_same(camera_at({centre_.x, centre_.y, hi_.z + 400}, 30.0, -90.0, 160, 90), 8000);
}

TEST_F(ViewAutzen, FromGrazingAnglesEqualsTheReference) {
    // Yaw positive clockwise seen from above (docs/camera.md): each camera looks into the data.
    expect_same(camera_at({lo_.x + 10, centre_.y, hi_.z + 5}, -5.0, -4.0, 160, 90), 1000);
    expect_same(camera_at({hi_.x - 10, lo_.y + 10, lo_.z + 30}, -150.0, -1.0, 160, 90), 1000);
    expect_same(camera_at({centre_.x, centre_.y, lo_.z + 20}, -270.0, 0.0, 160, 90), 1000);
}

TEST_F(ViewAutzen, InEveryOctantEqualsTheReference) {
    for (const double yaw : {45.0, 135.0, 225.0, 315.0}) {
        for (const double pitch : {-25.0, 25.0}) {
            const double z = pitch < 0 ? hi_.z + 20 : lo_.z + 15;
            SCOPED_TRACE("yaw " + std::to_string(yaw) + " pitch " + std::to_string(pitch));
            expect_same(camera_at({centre_.x, centre_.y, z}, yaw, pitch, 96, 54), 200);
        }
    }
}

TEST_F(ViewAutzen, ImageDoesNotDependOnTheThreadCount) {
    const ViewCamera cam = camera_at({lo_.x, lo_.y, hi_.z + 50}, 30.0, -20.0, 120, 70);
    ThreadPool one(1);
    const ViewImage a = render_view(session_->grid(), cam, {}, one);
    const ViewImage b = session_->render(cam, {});
    EXPECT_EQ(a.rgb, b.rgb);
    EXPECT_EQ(a.depth, b.depth);
}

}  // namespace
}  // namespace beamtrace
