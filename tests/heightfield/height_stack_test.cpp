// Height stacks: several occupied height intervals per cell, so rays pass under bridges, wires
// and tree crowns. Checked against analytic distances and the brute-force reference renderer.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/heightfield/view_session.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

std::vector<float> stack_of(const HeightSection& s) {
    const float* p = s.stack(0, 0);
    return {p, p + 2 * s.stacks()};
}

TEST(HeightStack, IntervalsJoinWithinTheGapAndTheClosestMergeWhenFull) {
    HeightSection s({1, 1}, false, 2, 1.0f);
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_EQ(stack_of(s), (std::vector<float>{inf, -inf, inf, -inf}));
    s.insert(0, 0, 0.0f, 0);
    s.insert(0, 0, 0.5f, 0);  // within the gap: joins
    EXPECT_EQ(stack_of(s), (std::vector<float>{0.0f, 0.5f, inf, -inf}));
    s.insert(0, 0, 10.0f, 0);  // a second interval
    EXPECT_EQ(stack_of(s), (std::vector<float>{0.0f, 0.5f, 10.0f, 10.0f}));
    s.insert(0, 0, 5.0f, 0);  // a third: the closest pair (0.5 -> 5) merges
    EXPECT_EQ(stack_of(s), (std::vector<float>{0.0f, 5.0f, 10.0f, 10.0f}));
    s.insert(0, 0, 10.8f, 0);
    s.insert(0, 0, 6.5f, 0);  // within the gap of neither, merges 5 -> 6.5
    EXPECT_EQ(stack_of(s), (std::vector<float>{0.0f, 6.5f, 10.0f, 10.8f}));
    s.insert(0, 0, 7.5f, 0);  // joins [0, 6.5] and then comes within the gap of nothing else
    EXPECT_EQ(stack_of(s), (std::vector<float>{0.0f, 7.5f, 10.0f, 10.8f}));
    s.insert(0, 0, 8.5f, 0);  // joins [0, 7.5]; 1.5 below the next: still apart
    EXPECT_EQ(stack_of(s), (std::vector<float>{0.0f, 8.5f, 10.0f, 10.8f}));
    s.insert(0, 0, 9.0f, 0);  // joins [0, 8.5], which comes within the gap of the next: one
    EXPECT_EQ(stack_of(s), (std::vector<float>{0.0f, 10.8f, inf, -inf}));
    s.build_mipmap();
    EXPECT_FLOAT_EQ(s.height(0, 0, 0), 10.8f);  // the max mipmap is unchanged by stacks
    EXPECT_EQ(HeightSection::bytes_for({1, 1}, false, 2) - HeightSection::bytes_for({1, 1}, false),
              4 * sizeof(float));
}

/// Ground at z = 0 in every 1 m cell of [0.5, 32.5)^2 and a 10 m high bridge over x in
/// [14.5, 18.5), written to a LAS file and read by a session.
class HeightStackBridge : public test::TempDirTest {
  protected:
    void SetUp() override { las_ = test::write_bridge_las(dir_ / "bridge.las"); }

    [[nodiscard]] ViewImage render(int stacks, const Vec3d& position, double pitch_deg) const {
        const ViewSessionConfig c = test::bridge_view_config(stacks);
        ViewSession session(std::span(&las_, 1), c);
        static_cast<void>(session.move_to(position));
        ViewCamera cam;
        cam.position = position;
        cam.yaw_deg = 0.0;
        cam.pitch_deg = pitch_deg;
        cam.width = 101;  // odd: the middle pixel looks exactly along yaw/pitch
        cam.height = 51;
        const ViewImage image = session.render(cam, {});
        const ViewImage reference = render_view_reference(session.grid(), cam, {}, session.pool());
        std::string first;
        EXPECT_EQ(test::count_mismatches(image, reference, first), 0u) << first;
        return image;
    }

    [[nodiscard]] static float middle_depth(const ViewImage& image) {
        return image.depth[static_cast<std::size_t>(25 * 101 + 50)];
    }

    std::filesystem::path las_;
};

TEST_F(HeightStackBridge, AGrazingRayPassesUnderTheBridge) {
    const double pitch = -10.0;
    const double rad = pitch * std::numbers::pi / 180.0;
    const Vec3d camera = {2.0, 16.3, 4.0};
    // With stacks: under the bridge (z = 1.1 to 1.8 there) down to the ground at z = 0.
    const ViewImage stacked = render(2, camera, pitch);
    EXPECT_NEAR(middle_depth(stacked), 4.0 / std::sin(-rad), 1e-4);
    // Without: the bridge's column reaches the ground, the ray hits its side at x = 14.5.
    const ViewImage columns = render(0, camera, pitch);
    EXPECT_NEAR(middle_depth(columns), 12.5 / std::cos(rad), 1e-4);
    EXPECT_GT(stacked.hits(), stacked.depth.size() / 3);
}

TEST_F(HeightStackBridge, LookingUpFromBeneathSeesTheUnderside) {
    const double pitch = 80.0;
    const ViewImage image = render(2, {16.0, 16.3, 3.0}, pitch);
    EXPECT_NEAR(middle_depth(image), 7.0 / std::sin(pitch * std::numbers::pi / 180.0), 1e-4);
}

TEST(HeightStack, HierarchyEqualsTheBruteForceReferenceWithOverhangs) {
    HeightFieldConfig config;
    config.cell_size = 0.5;
    config.levels = 4;
    config.section_cells = 2;  // 16 cells per section
    config.sections = 3;
    config.height_stacks = 3;
    config.stack_gap = 0.75;
    config.color = ColorMode::intensity;
    SectionGrid grid(config, {0, 0, 0});
    const std::int64_t w = grid.window_cells();
    const std::vector<Bounds2> all = {
        {0, 0, static_cast<double>(w) * 0.5, static_cast<double>(w) * 0.5}};
    const std::vector<int> slots =
        grid.recenter(static_cast<double>(w) * 0.25, static_cast<double>(w) * 0.25, all, 0);
    ASSERT_EQ(slots.size(), 9u);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int shift = grid.layout().finest_shift();
    const auto insert = [&](std::int64_t x, std::int64_t y, double z) {
        HeightSection* s = grid.slot(static_cast<int>((y >> shift) * 3 + (x >> shift)));
        const std::int64_t mask = (std::int64_t{1} << shift) - 1;
        s->insert(static_cast<int>(x & mask), static_cast<int>(y & mask), static_cast<float>(z),
                  static_cast<std::uint32_t>(x + 7 * y));
    };
    for (std::int64_t y = 0; y < w; ++y) {
        for (std::int64_t x = 0; x < w; ++x) {
            if (u(rng) < 0.1) {
                continue;  // holes
            }
            const double ground = 2.0 * std::sin(0.2 * static_cast<double>(x)) *
                                      std::cos(0.15 * static_cast<double>(y)) +
                                  0.3 * u(rng);
            insert(x, y, ground);
            if (x >= 20 && x < 26) {
                insert(x, y, 6.0 + 0.1 * u(rng));  // a bridge deck
            }
            if (x == y || x == y + 1) {
                insert(x, y, ground + 9.0);  // a wire
            }
            if (u(rng) < 0.15) {
                insert(x, y, ground + 3.0 + u(rng));  // crowns
                insert(x, y, ground + 4.5 + u(rng));
            }
        }
    }
    for (const int s : slots) {
        grid.slot(s)->build_mipmap();
        grid.mark_loaded(s);
    }
    ThreadPool pool(2);
    RenderOptions options;
    options.fog_distance = 40.0;
    int cameras = 0;
    for (const double yaw : {5.0, 100.0, 190.0, 275.0, 45.0}) {
        for (const double pitch : {-50.0, -8.0, 0.0, 12.0, 70.0}) {
            for (const Vec3d p : {Vec3d{11.5, 12.2, 3.0}, Vec3d{-2.0, 3.0, 8.0},
                                  Vec3d{13.0, 20.7, 12.0}, Vec3d{3.1, 2.9, 1.0}}) {
                ViewCamera cam;
                cam.position = p;
                cam.yaw_deg = yaw;
                cam.pitch_deg = pitch;
                cam.width = 48;
                cam.height = 32;
                const ViewImage fast = render_view(grid, cam, options, pool);
                const ViewImage slow = render_view_reference(grid, cam, options, pool);
                std::string first;
                EXPECT_EQ(test::count_mismatches(fast, slow, first), 0u)
                    << "yaw " << yaw << " pitch " << pitch << " at " << p.x << "," << p.y << ","
                    << p.z << ": " << first;
                ++cameras;
            }
        }
    }
    EXPECT_EQ(cameras, 100);
}

}  // namespace
}  // namespace beamtrace
