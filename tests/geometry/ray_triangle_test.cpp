#include "beamtrace/geometry/ray_triangle.hpp"

#include <gtest/gtest.h>

#include <random>

#include "beamtrace/geometry/moller_trumbore.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

// Triangle in the plane z = 0, counter-clockwise seen from +z (front faces +z).
const Vec3f kA{0, 0, 0}, kB{1, 0, 0}, kC{0, 1, 0};

bool hit_tri(const Vec3f& o, const Vec3f& d, Facing facing, TriangleHit& h) {
    return intersect_watertight(make_watertight_ray(o, d), kA, kB, kC, 0.0f,
                                std::numeric_limits<float>::infinity(), facing, h);
}

TEST(Watertight, HitsInteriorPointWithRangeAndBarycentrics) {
    TriangleHit h;
    ASSERT_TRUE(hit_tri({0.25f, 0.5f, 3.0f}, {0, 0, -1}, Facing::both, h));
    EXPECT_FLOAT_EQ(h.t, 3.0f);
    EXPECT_FLOAT_EQ(h.u, 0.25f);  // weight of B = x
    EXPECT_FLOAT_EQ(h.v, 0.5f);   // weight of C = y
    EXPECT_TRUE(h.front);
}

TEST(Watertight, FacingSelectsSides) {
    TriangleHit h;
    // From above (+z) the ray meets the front.
    EXPECT_TRUE(hit_tri({0.2f, 0.2f, 1.0f}, {0, 0, -1}, Facing::front, h));
    EXPECT_FALSE(hit_tri({0.2f, 0.2f, 1.0f}, {0, 0, -1}, Facing::back, h));
    // From below it meets the back.
    EXPECT_FALSE(hit_tri({0.2f, 0.2f, -1.0f}, {0, 0, 1}, Facing::front, h));
    ASSERT_TRUE(hit_tri({0.2f, 0.2f, -1.0f}, {0, 0, 1}, Facing::back, h));
    EXPECT_FALSE(h.front);
    // Oblique rays, every dominant axis and sign.
    for (int axis = 0; axis < 3; ++axis) {
        for (float sign : {-1.0f, 1.0f}) {
            Vec3f d{0.1f, 0.15f, 0.0f};
            d[static_cast<std::size_t>(axis)] = 3.0f * sign;
            d.z = d.z == 0.0f ? (axis == 2 ? 3.0f * sign : -0.5f) : d.z;
            const Vec3f target{0.2f, 0.3f, 0.0f};
            const Vec3f o = target - d * 2.0f;
            const bool expect_front = d.z < 0.0f;
            ASSERT_TRUE(hit_tri(o, d, Facing::both, h)) << axis << " " << sign;
            EXPECT_EQ(h.front, expect_front) << axis << " " << sign;
            EXPECT_NEAR(h.t, 2.0f, 1e-5f);
        }
    }
}

TEST(Watertight, NoHitsBehindOriginOrOutside) {
    TriangleHit h;
    EXPECT_FALSE(hit_tri({0.2f, 0.2f, 1.0f}, {0, 0, 1}, Facing::both, h));   // behind
    EXPECT_FALSE(hit_tri({0.8f, 0.8f, 1.0f}, {0, 0, -1}, Facing::both, h));  // outside
    EXPECT_FALSE(hit_tri({0.2f, 0.2f, 1.0f}, {1, 0, 0}, Facing::both, h));   // parallel
    // Within [tmin, tmax] only.
    const auto r = make_watertight_ray({0.2f, 0.2f, 5.0f}, {0, 0, -1});
    EXPECT_FALSE(intersect_watertight(r, kA, kB, kC, 0.0f, 4.0f, Facing::both, h));
    EXPECT_FALSE(intersect_watertight(r, kA, kB, kC, 5.5f, 9.0f, Facing::both, h));
    EXPECT_TRUE(intersect_watertight(r, kA, kB, kC, 0.0f, 5.0f, Facing::both, h));
}

TEST(Watertight, SharedEdgeAndVertexNeverLeak) {
    // Two triangles of a square share the diagonal; rays exactly on it hit at least one.
    const Vec3f p0{0, 0, 0}, p1{1, 0, 0}, p2{1, 1, 0}, p3{0, 1, 0};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) {
        const float s = uni(rng);
        const Vec3f on_diag{s, s, 0};
        const Vec3f d = normalize(Vec3f{uni(rng) - 0.5f, uni(rng) - 0.5f, -1.0f});
        const Vec3f o = on_diag - d * 3.0f;
        const auto r = make_watertight_ray(o, d);
        TriangleHit h1, h2;
        const bool a = intersect_watertight(r, p0, p1, p2, 0, 1e30f, Facing::both, h1);
        const bool b = intersect_watertight(r, p0, p2, p3, 0, 1e30f, Facing::both, h2);
        ASSERT_TRUE(a || b) << "ray " << i << " leaked through the shared edge";
    }
}

TEST(MollerTrumbore, CullModesAndPositiveRangesOnly) {
    const TriangleMesh sphere = test::make_icosphere(2, 1.0f);
    // From outside along -x: one front hit (entering) and one back hit (leaving).
    const Vec3d o{5.0, 0.013, 0.021}, d{-1.0, 0.0, 0.0};
    const auto front = ray_intersect_all(sphere, o, d, Facing::front);
    const auto back = ray_intersect_all(sphere, o, d, Facing::back);
    const auto both = ray_intersect_all(sphere, o, d, Facing::both);
    ASSERT_EQ(front.size(), 1u);
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(both.size(), 2u);
    EXPECT_LT(front[0].t, back[0].t);
    EXPECT_NEAR(front[0].t, 4.0, 0.02);  // the icosphere's faces lie just inside the unit sphere
    // The intersection point is (1-u-v) V0 + u V1 + v V2 and lies on the ray.
    const Vec3d expect = o + d * front[0].t;
    EXPECT_NEAR(front[0].point.x, expect.x, 1e-9);
    EXPECT_NEAR(front[0].point.y, expect.y, 1e-9);
    // From the centre: only the back side is met, and never behind the origin.
    const Vec3d d_in = normalize(Vec3d{-1.0, 0.031, 0.017});  // off the mesh's symmetry axes
    const auto inside = ray_intersect_all(sphere, {0, 0, 0}, d_in, Facing::both);
    ASSERT_EQ(inside.size(), 1u);
    EXPECT_GT(inside[0].t, 0.9);
    EXPECT_TRUE(ray_intersect_all(sphere, {0, 0, 0}, d_in, Facing::front).empty());
    // Pointing away from the sphere: nothing (the Matlab code would return negative t).
    EXPECT_TRUE(ray_intersect_all(sphere, o, {1, 0, 0}, Facing::both).empty());
}

TEST(MollerTrumbore, AgreesWithWatertightOnRandomRays) {
    const TriangleMesh sphere = test::make_icosphere(1, 2.0f);
    std::mt19937 rng(3);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < 500; ++i) {
        const Vec3d o = normalize(Vec3d{g(rng), g(rng), g(rng)}) * 6.0;
        const Vec3d target{0.5 * g(rng), 0.5 * g(rng), 0.5 * g(rng)};
        const Vec3d d = normalize(target - o);
        const auto mt = ray_intersect_all(sphere, o, d, Facing::both);
        const auto r = make_watertight_ray(Vec3f(o), Vec3f(d));
        std::size_t wt = 0;
        for (const auto& f : sphere.faces) {
            TriangleHit h;
            wt += intersect_watertight(r, sphere.vertices[f[0]], sphere.vertices[f[1]],
                                       sphere.vertices[f[2]], 0, 1e30f, Facing::both, h)
                      ? 1
                      : 0;
        }
        EXPECT_EQ(mt.size(), wt) << "ray " << i;
    }
}

}  // namespace
}  // namespace beamtrace
