// Exact spheres in SceneGeometry: face IDs between instances, the flattened copy, normals, known
// ranges from outside and inside for every backend, and every backend against brute force on a
// scene of exact spheres mixed with instanced and flat triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/geometry/ray_sphere.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

std::vector<BackendKind> all_kinds() {
    return test::backends();
}

/// Instanced icospheres, a flat grid and exact spheres, interleaved so that sphere IDs fall
/// between instance ranges; one exact sphere cuts through the grid and one overlaps another.
SceneGeometry mixed_scene() {
    SceneGeometry g;
    const std::uint32_t ico = g.add_mesh(test::make_icosphere(2, 1.0f));
    Affine3 a;
    a.translation = {-3.0, 0.0, 0.5};
    g.add_instance(ico, a);                   // faces 0..319
    g.add_sphere({0.0f, 0.0f, 0.0f}, 1.5f);   // face 320, cut by the grid at z = 0
    g.append_flat(test::make_grid(8, 0.0f));  // faces 321..448 (grid over [0, 8]^2)
    g.add_sphere({3.0f, 3.0f, 1.0f}, 0.8f);   // 449
    g.add_sphere({3.5f, 3.2f, 1.2f}, 0.6f);   // 450, overlaps 449
    Affine3 b;
    b.linear.m = {{{1.5, 0, 0}, {0, 0.7, 0}, {0, 0, 1.0}}};
    b.translation = {5.0, -2.0, 1.0};
    g.add_instance(ico, b);                  // 451..770
    g.add_sphere({6.0f, 6.0f, 0.5f}, 2.0f);  // 771
    return g;
}

RayBatch rays_at(const Aabb& b, std::size_t n, unsigned seed) {
    return test::rays_toward(b, n, seed);
}

/// How far ray i's line passes from the surface of the nearest exact sphere, relative to its
/// radius: near zero for grazing rays, where single and double precision may disagree on a hit.
double grazing(const SceneGeometry& g, const RayBatch& rays, std::size_t i) {
    double best = 1e9;
    for (const auto& s : g.spheres) {
        const Vec3d f = rays.origin(i) - Vec3d(s.center);
        const Vec3d d = rays.direction(i);
        const Vec3d closest = f - d * dot(f, d);
        best = std::min(best, std::fabs(length(closest) - s.radius) / s.radius);
    }
    return best;
}

TEST(ExactSphere, FaceIdsInterleaveWithInstancesAndTheFlatCopyKeepsThem) {
    const SceneGeometry g = mixed_scene();
    EXPECT_EQ(g.face_count(), 772u);
    EXPECT_EQ(g.triangle_count(), 768u);
    EXPECT_EQ(g.instances[1].first_face, 321u);
    EXPECT_EQ(g.instances[2].first_face, 451u);
    ASSERT_EQ(g.spheres.size(), 4u);
    EXPECT_EQ(g.spheres[0].face, 320u);
    EXPECT_EQ(g.spheres[3].face, 771u);
    EXPECT_EQ(g.sphere_of_face(449), &g.spheres[1]);
    EXPECT_EQ(g.sphere_of_face(771), &g.spheres[3]);
    EXPECT_EQ(g.sphere_of_face(448), nullptr);
    EXPECT_EQ(g.sphere_of_face(319), nullptr);
    EXPECT_EQ(g.instance_of_face(321), 1u);
    EXPECT_EQ(g.instance_of_face(451), 2u);
    EXPECT_FALSE(g.is_single_mesh());
    // The bounds hold the largest sphere.
    EXPECT_LE(g.bounds().hi.x, 8.0f + 1e-5f);
    EXPECT_GE(g.bounds().hi.z, 2.5f);
    EXPECT_LE(g.bounds().lo.z, -1.5f);

    const TriangleMesh flat = g.flatten();
    ASSERT_EQ(flat.triangle_count(), g.face_count());
    for (const auto& s : g.spheres) {
        const Face& f = flat.faces[s.face];
        EXPECT_EQ(f[0], f[1]);
        EXPECT_EQ(f[1], f[2]);
        EXPECT_EQ(flat.vertices[f[0]].x, s.center.x);
    }
    for (std::uint32_t face : {0u, 321u, 448u, 451u, 770u}) {
        const auto t = g.triangle(face);
        const Face& f = flat.faces[face];
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_NEAR(flat.vertices[f[k]].x, t[k].x, 1e-5) << face;
        }
    }

    // Normals: a sphere's points outward through the point, a triangle's is its own.
    const Vec3d n = g.normal_at(449, {3.0, 3.0 + 0.8 * 0.6, 1.0 + 0.8 * 0.8});
    EXPECT_NEAR(n.y, 0.6, 1e-6);
    EXPECT_NEAR(n.z, 0.8, 1e-6);
    const Vec3d m = g.normal_at(330, {0, 0, 0});
    EXPECT_NEAR(std::fabs(m.z), 1.0, 1e-12);

    SceneGeometry bad;
    EXPECT_THROW(bad.add_sphere({0, 0, 0}, 0.0f), ConfigError);
    EXPECT_THROW(bad.add_sphere({0, 0, NAN}, 1.0f), ConfigError);
}

TEST(ExactSphere, KnownRangesFromOutsideAndInsideForEveryBackend) {
    SceneGeometry g;
    g.add_sphere({1.0f, 2.0f, 3.0f}, 2.0f);  // face 0
    ThreadPool pool(2);
    RayBatch rays;
    rays.push_back({1, 2, 13}, {0, 0, -1});                 // top at 8 m
    rays.push_back({1, 2, 3}, normalize(Vec3d{1, 1, 1}));   // from the centre: 2 m
    rays.push_back({1, 2, 13}, {0, 0, -1}, 9.0);            // past the entry: exit at 12 m
    rays.push_back({1, 2, 13}, {0, 0, -1}, 0.0, 7.9);       // stops short
    rays.push_back({3.5, 2, 13}, {0, 0, -1});               // misses (0.5 m beside)
    rays.push_back({-7, 2.0 + 1.2, 3.0 + 1.6}, {1, 0, 0});  // tangent at x = 1: 8 m
    for (const BackendKind kind : all_kinds()) {
        const auto backend = make_backend(kind, g, pool);
        const HitBatch h = backend->intersect(rays, pool);
        const std::string k(to_string(kind));
        ASSERT_TRUE(h.hit(0)) << k;
        EXPECT_EQ(h.face[0], 0u) << k;
        EXPECT_NEAR(h.t[0], 8.0f, 1e-5f) << k;
        EXPECT_NEAR(h.t[1], 2.0f, 1e-5f) << k;
        EXPECT_NEAR(h.t[2], 12.0f, 1e-5f) << k;
        EXPECT_FALSE(h.hit(3)) << k;
        EXPECT_FALSE(h.hit(4)) << k;
        if (h.hit(5)) {  // tangent to a float's precision: either is right, but at 8 m
            EXPECT_NEAR(h.t[5], 8.0f, 1e-2f) << k;
        }
        std::vector<std::uint8_t> occ;
        backend->occluded(rays, 0, 5, occ, pool);
        EXPECT_EQ(occ[0], 1) << k;
        EXPECT_EQ(occ[1], 1) << k;
        EXPECT_EQ(occ[2], 1) << k;
        EXPECT_EQ(occ[3], 0) << k;
        EXPECT_EQ(occ[4], 0) << k;

        // All hits: the entry is the front side, the exit the back; from inside only the back.
        RayBatch two;
        two.push_back({1, 2, 13}, {0, 0, -1});
        two.push_back({1, 2, 3}, {0, 0, 1});
        AllHits all;
        backend->intersect_all(two, Facing::both, all, pool);
        ASSERT_EQ(all.count(0), 2u) << k;
        EXPECT_NEAR(all.t[0], 8.0f, 1e-5f) << k;
        EXPECT_EQ(all.front[0], 1) << k;
        EXPECT_NEAR(all.t[1], 12.0f, 1e-5f) << k;
        EXPECT_EQ(all.front[1], 0) << k;
        ASSERT_EQ(all.count(1), 1u) << k;
        EXPECT_NEAR(all.t[2], 2.0f, 1e-5f) << k;
        EXPECT_EQ(all.front[2], 0) << k;
        backend->intersect_all(two, Facing::front, all, pool);
        ASSERT_EQ(all.count(0), 1u) << k;
        EXPECT_NEAR(all.t[0], 8.0f, 1e-5f) << k;
        EXPECT_EQ(all.count(1), 0u) << k;
        backend->intersect_all(two, Facing::back, all, pool);
        ASSERT_EQ(all.count(0), 1u) << k;
        EXPECT_NEAR(all.t[0], 12.0f, 1e-5f) << k;
        EXPECT_EQ(all.count(1), 1u) << k;
    }
}

TEST(ExactSphere, EveryBackendAgreesWithBruteForceOnAMixedScene) {
    const SceneGeometry g = mixed_scene();
    ThreadPool pool(2);
    const RayBatch rays = rays_at(g.bounds(), test::heavy_scale(20000), 5);
    const auto brute = make_backend(BackendKind::brute, g, pool);
    const HitBatch oracle = brute->intersect(rays, pool);
    std::vector<std::uint8_t> occ_oracle;
    brute->occluded(rays, 0, rays.size(), occ_oracle, pool);
    AllHits all_oracle;
    brute->intersect_all(rays, Facing::both, all_oracle, pool);

    // The oracle itself: a hit on a sphere lies on it, and the spheres, the grid and both
    // instances are all hit.
    std::size_t sphere_hits[4] = {0, 0, 0, 0}, triangle_hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!oracle.hit(i)) {
            continue;
        }
        if (const ExactSphere* s = g.sphere_of_face(oracle.face[i])) {
            ++sphere_hits[s - g.spheres.data()];
            const Vec3d p = rays.origin(i) + rays.direction(i) * double(oracle.t[i]);
            EXPECT_NEAR(length(p - Vec3d(s->center)), s->radius, 1e-5 * length(p)) << i;
        } else {
            ++triangle_hits;
        }
    }
    for (const std::size_t n : sphere_hits) {
        EXPECT_GT(n, rays.size() / 200);
    }
    EXPECT_GT(triangle_hits, rays.size() / 10);

    for (const BackendKind kind : all_kinds()) {
        if (kind == BackendKind::brute) {
            continue;
        }
        const auto backend = make_backend(kind, g, pool);
        const std::string k(to_string(kind));
        // Our backends run the same sphere arithmetic as brute force: exact agreement. Embree's
        // single-precision roots may disagree on grazing rays only.
        const bool exact = kind != BackendKind::embree;
        const HitBatch got = backend->intersect(rays, pool);
        std::size_t disagree = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (got.hit(i) != oracle.hit(i) ||
                (got.hit(i) && got.face[i] != oracle.face[i] &&
                 std::fabs(got.t[i] - oracle.t[i]) > 1e-5f * oracle.t[i])) {
                ++disagree;
                ASSERT_FALSE(exact) << k << " ray " << i;
                ASSERT_LT(grazing(g, rays, i), 1e-4) << k << " ray " << i;
                continue;
            }
            if (got.hit(i)) {
                ASSERT_NEAR(got.t[i], oracle.t[i], (exact ? 1e-6f : 2e-6f) * oracle.t[i])
                    << k << " ray " << i;
            }
        }
        EXPECT_LE(disagree, rays.size() / 1000) << k;

        std::vector<std::uint8_t> occ;
        backend->occluded(rays, 0, rays.size(), occ, pool);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (occ[i] != occ_oracle[i]) {
                ASSERT_FALSE(exact) << k << " ray " << i;
                ASSERT_LT(grazing(g, rays, i), 1e-4) << k << " ray " << i;
            }
        }

        AllHits all;
        backend->intersect_all(rays, Facing::both, all, pool);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const auto want = all_oracle.offsets[i], have = all.offsets[i];
            if (all.count(i) != all_oracle.count(i)) {
                ASSERT_FALSE(exact) << k << " ray " << i;
                ASSERT_LT(grazing(g, rays, i), 1e-4) << k << " ray " << i;
                continue;
            }
            for (std::size_t j = 0; j < all.count(i); ++j) {
                const std::size_t a = have + j, b = want + j;
                if (all.face[a] == all_oracle.face[b]) {
                    ASSERT_EQ(all.front[a], all_oracle.front[b])
                        << k << " ray " << i << " hit " << j;
                    continue;
                }
                // Two faces at one range (a shared edge) may come in either order in Embree.
                ASSERT_FALSE(exact) << k << " ray " << i << " hit " << j;
                ASSERT_NEAR(all.t[a], all_oracle.t[b], 2e-6f * all_oracle.t[b])
                    << k << " ray " << i;
            }
        }
    }
}

TEST(ExactSphere, ASceneOfSpheresOnlyTracesInEveryBackend) {
    // No triangles at all: a row of spheres seen end on; the ray meets the first one.
    SceneGeometry g;
    for (int k = 0; k < 5; ++k) {
        g.add_sphere({static_cast<float>(4 * k), 0.0f, 0.0f}, 1.0f);
    }
    ThreadPool pool(1);
    RayBatch rays;
    rays.push_back({-10, 0, 0}, {1, 0, 0});
    rays.push_back({30, 0.5, 0}, {-1, 0, 0});
    rays.push_back({8, 0, 10}, {0, 0, -1});
    for (const BackendKind kind : all_kinds()) {
        const HitBatch h = make_backend(kind, g, pool)->intersect(rays, pool);
        const std::string k(to_string(kind));
        EXPECT_EQ(h.face[0], 0u) << k;
        EXPECT_NEAR(h.t[0], 9.0f, 1e-5f) << k;
        EXPECT_EQ(h.face[1], 4u) << k;
        EXPECT_NEAR(h.t[1], 14.0 - std::sqrt(0.75), 1e-5) << k;
        EXPECT_EQ(h.face[2], 2u) << k;
        EXPECT_NEAR(h.t[2], 9.0f, 1e-5f) << k;
    }
}

}  // namespace
}  // namespace beamtrace
