// Ranges to planes and boxes at known distances, for every backend.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/image_sensor.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TriangleMesh make_box_mesh(const Vec3f& lo, const Vec3f& hi) {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i) {
        m.vertices.emplace_back((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y,
                                (i & 4) ? hi.z : lo.z);
    }
    m.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
               {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    return m;
}

class Analytic : public ::testing::TestWithParam<BackendKind> {};

TEST_P(Analytic, PlaneAtKnownHeightGivesHOverCosTheta) {
    // A 2 km x 2 km ground plane z = 0 seen by a nadir-looking pinhole 100 m up.
    TriangleMesh plane = test::make_grid(40);
    for (auto& v : plane.vertices) {
        v = Vec3f(v.x * 50.0f - 1000.0f, v.y * 50.0f - 1000.0f, 0.0f);
    }
    ThreadPool pool(2);
    const auto backend = make_backend(GetParam(), plane, pool);
    ImageSensorConfig cam;
    cam.position_m = {3.0, -7.0, 100.0};
    cam.orientation = {0.0, -std::numbers::pi / 2, 0.3};
    cam.width = 64;
    cam.height = 48;
    cam.hfov_rad = 1.2;
    cam.vfov_rad = 0.9;
    const RayBatch rays = cast_rays_pinhole(cam);
    const HitBatch hits = backend->intersect(rays, pool);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(hits.hit(i)) << i;
        const double cos_theta = -rays.dz[i];
        EXPECT_NEAR(hits.t[i], 100.0 / cos_theta, 2e-6 * 100.0 / cos_theta) << i;
    }
}

TEST_P(Analytic, BoxFromOutsideAndInside) {
    const TriangleMesh box = make_box_mesh({-1, -2, -3}, {1, 2, 3});
    ThreadPool pool(1);
    const auto backend = make_backend(GetParam(), box, pool);
    RayBatch rays;
    rays.push_back({10, 0.3, 0.2}, {-1, 0, 0});            // x = +1 face at 9 m
    rays.push_back({0.1, -12, 0.5}, {0, 1, 0});            // y = -2 face at 10 m
    rays.push_back({0.2, 0.4, -7.5}, {0, 0, 1});           // z = -3 face at 4.5 m
    rays.push_back({0, 0, 0}, {0, 0, 1});                  // from inside: z = 3 at 3 m
    rays.push_back({0, 0, 0}, normalize(Vec3d{1, 1, 0}));  // inside, diagonal: x = 1 at sqrt 2
    rays.push_back({10, 5, 0}, {-1, 0, 0});                // misses (y = 5 outside)
    rays.push_back({10, 0, 0}, {1, 0, 0});                 // box behind the origin: no hit
    const HitBatch hits = backend->intersect(rays, pool);
    EXPECT_FLOAT_EQ(hits.t[0], 9.0f);
    EXPECT_FLOAT_EQ(hits.t[1], 10.0f);
    EXPECT_FLOAT_EQ(hits.t[2], 4.5f);
    EXPECT_FLOAT_EQ(hits.t[3], 3.0f);
    EXPECT_NEAR(hits.t[4], std::sqrt(2.0), 1e-6);
    EXPECT_FALSE(hits.hit(5));
    EXPECT_FALSE(hits.hit(6));
    EXPECT_EQ(hits.face[5], kNoFace);
    EXPECT_TRUE(std::isinf(hits.t[5]));
    // Face IDs: x = +1 is faces 10/11, y = lo is 4/5, z = lo is 0/1, z = hi is 2/3.
    EXPECT_TRUE(hits.face[0] == 10 || hits.face[0] == 11);
    EXPECT_TRUE(hits.face[1] == 4 || hits.face[1] == 5);
    EXPECT_TRUE(hits.face[2] == 0 || hits.face[2] == 1);
    EXPECT_TRUE(hits.face[3] == 2 || hits.face[3] == 3);
}

TEST_P(Analytic, RangeLimitsAreHonoured) {
    const TriangleMesh box = make_box_mesh({-1, -1, -1}, {1, 1, 1});
    ThreadPool pool(1);
    const auto backend = make_backend(GetParam(), box, pool);
    RayBatch rays;
    rays.push_back({5, 0, 0}, {-1, 0, 0}, 0.0, 3.9);  // stops short of the box
    rays.push_back({5, 0, 0}, {-1, 0, 0}, 4.5, 100);  // starts inside: next face at 6
    const HitBatch hits = backend->intersect(rays, pool);
    EXPECT_FALSE(hits.hit(0));
    EXPECT_FLOAT_EQ(hits.t[1], 6.0f);
}

TEST_P(Analytic, EmptySceneMissesEverything) {
    const TriangleMesh empty;
    ThreadPool pool(1);
    const auto backend = make_backend(GetParam(), empty, pool);
    RayBatch rays;
    rays.push_back({0, 0, 0}, {1, 0, 0});
    EXPECT_FALSE(backend->intersect(rays, pool).hit(0));
}

/// Every backend this build has: Embree, the default backend, too where it is built.
std::vector<BackendKind> built_backends() {
    return test::backends(true, false);
}

INSTANTIATE_TEST_SUITE_P(AllBackends, Analytic, ::testing::ValuesIn(built_backends()),
                         [](const ::testing::TestParamInfo<BackendKind>& p) {
                             return std::string(to_string(p.param));
                         });

// The analytic tests above cover the default backend: a build without Embree runs them on our
// own backends only, which fails under BEAMTRACE_REQUIRE_ALL=1 (CI builds with Embree).
TEST(AnalyticBackends, IncludeTheDefaultBackend) {
    const auto kinds = built_backends();
    EXPECT_NE(std::find(kinds.begin(), kinds.end(), default_backend_kind()), kinds.end());
    if (!embree_available()) {
        BEAMTRACE_SKIP_OR_FAIL(
            "built without Embree, the default backend: the analytic tests did not check it "
            "(install libembree-dev and reconfigure)");
    }
    EXPECT_NE(std::find(kinds.begin(), kinds.end(), BackendKind::embree), kinds.end());
}

TEST(BackendKind, ParsesNamesAndRejectsOthers) {
    EXPECT_EQ(parse_backend_kind("bvh"), BackendKind::bvh);
    EXPECT_EQ(parse_backend_kind("kdtree"), BackendKind::kdtree);
    EXPECT_EQ(parse_backend_kind("brute"), BackendKind::brute);
    if (embree_available()) {
        EXPECT_EQ(parse_backend_kind("embree"), BackendKind::embree);
    } else {
        EXPECT_THROW((void)parse_backend_kind("embree"), ConfigError);
    }
    EXPECT_THROW((void)parse_backend_kind("embree2"), ConfigError);
}

}  // namespace
}  // namespace beamtrace
