// Instanced geometry: the two-level BVH against brute force over the flattened copy, global face
// IDs, mirrored placements, and a large array traced without copying triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

Affine3 placement(const Vec3d& t, const RollPitchYaw& rpy, const Vec3d& scale) {
    PartTransform p;
    p.translate_m = t;
    p.rotate = rpy;
    p.scale = scale;
    return p.to_affine();
}

/// Two meshes: a sphere placed four times (rotated, non-uniformly scaled, one mirrored), a flat
/// grid placed with the identity, and the sphere again, so instances interleave meshes.
SceneGeometry mixed_scene(const TriangleMesh& object) {
    SceneGeometry g;
    const std::uint32_t obj = g.add_mesh(object);
    g.add_instance(obj, placement({0, 0, 0}, {0, 0, 0}, {1, 1, 1}));
    g.add_instance(obj, placement({3, 0.5, 0}, {0.3, -0.2, 1.1}, {1.5, 0.7, 1.0}));
    g.add_instance(obj, placement({-2.5, 2, 1}, {1.0, 0.4, -0.6}, {-1.0, 1.2, 0.9}));  // mirror
    g.append_flat(test::make_grid(8, -2.0f));
    g.add_instance(obj, placement({0.5, -3, 0.5}, {0, 0, 0.7}, {0.6, 0.6, 0.6}));
    return g;
}

RayBatch rays_at(const Aabb& b, std::size_t n, unsigned seed) {
    return test::rays_toward(b, n, seed);
}

TEST(SceneGeometry, FaceIdsAreGlobalAndTrianglesArePlaced) {
    const TriangleMesh sphere = test::make_icosphere(1, 1.0f);
    const SceneGeometry g = mixed_scene(sphere);
    ASSERT_EQ(g.meshes.size(), 2u);
    ASSERT_EQ(g.instances.size(), 5u);
    EXPECT_EQ(g.triangle_count(), 4 * 80u + 128u);
    EXPECT_EQ(g.stored_triangle_count(), 80u + 128u);
    EXPECT_FALSE(g.is_single_mesh());
    EXPECT_EQ(g.instances[3].first_face, 240u);
    EXPECT_EQ(g.instances[4].first_face, 368u);
    EXPECT_EQ(g.instance_of_face(0), 0u);
    EXPECT_EQ(g.instance_of_face(239), 2u);
    EXPECT_EQ(g.instance_of_face(240), 3u);
    EXPECT_EQ(g.instance_of_face(447), 4u);
    // Face 80 + 7 is face 7 of the sphere mapped by instance 1.
    const auto t = g.triangle(87);
    const Vec3d a = g.instances[1].to_world.apply_point(Vec3d(sphere.vertices[sphere.faces[7][0]]));
    EXPECT_NEAR(t[0].x, a.x, 1e-12);
    EXPECT_NEAR(t[0].z, a.z, 1e-12);
    // The flattened copy has the same faces in the same order.
    const TriangleMesh flat = g.flatten();
    ASSERT_EQ(flat.triangle_count(), g.triangle_count());
    for (std::uint32_t f : {0u, 87u, 200u, 250u, 400u}) {
        const auto w = g.triangle(f);
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_NEAR(flat.vertices[flat.faces[f][k]].y, w[k].y, 1e-5) << f;
        }
    }
    // Bounds hold every placed vertex.
    const Aabb box = g.bounds();
    for (const auto& v : flat.vertices) {
        EXPECT_TRUE(v.x >= box.lo.x && v.x <= box.hi.x && v.z >= box.lo.z && v.z <= box.hi.z);
    }
}

TEST(SceneGeometry, ConsecutiveFlatPartsShareOneMeshAndSingularTransformsAreRefused) {
    SceneGeometry g;
    g.append_flat(test::make_grid(2));
    g.append_flat(test::make_grid(3));
    EXPECT_TRUE(g.is_single_mesh());
    EXPECT_EQ(g.meshes.size(), 1u);
    EXPECT_EQ(g.triangle_count(), 8u + 18u);
    const std::uint32_t m = g.add_mesh(test::make_grid(1));
    Affine3 flat_z;
    flat_z.linear.m[2][2] = 0.0;
    EXPECT_THROW(g.add_instance(m, flat_z), ConfigError);
    EXPECT_THROW(g.add_instance(7, Affine3{}), ConfigError);
    g.add_instance(m, Affine3{});
    g.append_flat(test::make_grid(1));  // a new mesh: mesh m may be instanced again later
    EXPECT_EQ(g.meshes.size(), 3u);
    EXPECT_EQ(g.meshes[m].triangle_count(), 2u);
}

TEST(SceneGeometry, AffineInverse) {
    const Affine3 a = placement({1, -2, 3}, {0.4, -0.3, 2.0}, {2.0, -0.5, 0.25});
    const Affine3 id = a.inverse() * a;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            EXPECT_NEAR(id.linear.m[i][j], i == j ? 1.0 : 0.0, 1e-12);
        }
        EXPECT_NEAR(id.translation[static_cast<std::size_t>(i)], 0.0, 1e-12);
    }
    EXPECT_LT(a.determinant(), 0.0);
}

TEST(Instancing, TwoLevelBvhAgreesWithBruteForceOnTheFlattenedScene) {
    const TriangleMesh sphere = test::make_icosphere(3, 1.0f);
    const SceneGeometry g = mixed_scene(sphere);
    ThreadPool pool(2);
    const RayBatch rays = rays_at(g.bounds(), test::heavy_scale(20000), 7);
    const auto brute = make_backend(BackendKind::brute, g, pool);
    std::vector<std::unique_ptr<Backend>> owned;
    std::vector<const Backend*> backends;
    for (const BackendKind kind : test::backends(false)) {
        owned.push_back(make_backend(kind, g, pool));
        backends.push_back(owned.back().get());
    }
    const HitBatch oracle = brute->intersect(rays, pool);
    std::size_t hits = 0, per_instance[5] = {0, 0, 0, 0, 0};
    for (const auto* backend : backends) {
        const HitBatch got = backend->intersect(rays, pool);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(got.hit(i), oracle.hit(i)) << to_string(backend->kind()) << " ray " << i;
            if (!oracle.hit(i)) {
                continue;
            }
            const bool same = got.face[i] == oracle.face[i] ||
                              std::fabs(got.t[i] - oracle.t[i]) <= 1e-5f * oracle.t[i];
            ASSERT_TRUE(same) << to_string(backend->kind()) << " ray " << i << ": face "
                              << got.face[i] << " vs " << oracle.face[i];
            EXPECT_NEAR(got.t[i], oracle.t[i], 1e-4f * oracle.t[i]);
        }
    }
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (oracle.hit(i)) {
            ++hits;
            ++per_instance[g.instance_of_face(oracle.face[i])];
        }
    }
    EXPECT_GT(hits, rays.size() / 3);
    for (std::size_t k = 0; k < 5; ++k) {
        EXPECT_GT(per_instance[k], 0u) << "instance " << k << " is never hit";
    }
    // Occlusion agrees.
    std::vector<std::uint8_t> occ_brute;
    brute->occluded(rays, 0, rays.size(), occ_brute, pool);
    for (const auto* backend : backends) {
        std::vector<std::uint8_t> occ;
        backend->occluded(rays, 0, rays.size(), occ, pool);
        EXPECT_EQ(occ_brute, occ) << to_string(backend->kind());
    }
}

TEST(Instancing, AllHitsAndFacingSurviveMirroredPlacements) {
    const TriangleMesh sphere = test::make_icosphere(2, 1.0f);
    const SceneGeometry g = mixed_scene(sphere);
    ThreadPool pool(2);
    const RayBatch rays = rays_at(g.bounds(), test::heavy_scale(4000), 11);
    const auto brute = make_backend(BackendKind::brute, g, pool);
    const auto bvh = make_backend(BackendKind::bvh, g, pool);
    const std::vector<BackendKind> kinds = test::backends(false);
    for (const BackendKind kind : kinds) {
        const auto backend = make_backend(kind, g, pool);
        for (const Facing facing : {Facing::both, Facing::front, Facing::back}) {
            AllHits want, got;
            brute->intersect_all(rays, facing, want, pool);
            backend->intersect_all(rays, facing, got, pool);
            ASSERT_EQ(want.offsets, got.offsets) << to_string(kind);
            EXPECT_EQ(want.face, got.face) << to_string(kind);
            EXPECT_EQ(want.front, got.front) << to_string(kind);
            EXPECT_GT(want.face.size(), rays.size() / (facing == Facing::both ? 3 : 5));
        }
    }
    // Every ray that enters the closed, outward-facing spheres from outside meets a front face
    // first, mirrored or not.
    AllHits all;
    bvh->intersect_all(rays, Facing::both, all, pool);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (all.offsets[i] < all.offsets[i + 1] &&
            all.face[all.offsets[i]] < 240u + 0u) {  // first hit on one of the first spheres
            EXPECT_EQ(all.front[all.offsets[i]], 1) << "ray " << i;
        }
    }
}

TEST(Instancing, LargeArrayTracesLikeTheSingleMesh) {
    // 40 x 40 copies of a 12 800-triangle grid: 20.5 M triangles, 12 800 stored.
    const TriangleMesh tile = test::make_grid(80);
    SceneGeometry g;
    const std::uint32_t m = g.add_mesh(tile);
    const int n = 40;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            Affine3 t;
            t.translation = {100.0 * i, 100.0 * j, 0.5 * ((i + j) % 3)};
            g.add_instance(m, t);
        }
    }
    EXPECT_EQ(g.triangle_count(), 1600u * 12800u);
    EXPECT_EQ(g.stored_triangle_count(), 12800u);
    ThreadPool pool(2);
    const auto bvh = make_backend(BackendKind::bvh, g, pool);
    const auto single = make_backend(BackendKind::bvh, tile, pool);
    // Rays straight down onto copy (i, j) meet the same local face as the tile, at the height
    // of that copy.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    // A point well inside one of the tile's triangles (float origins near x = 4000 m move by
    // ~0.2 mm, which must not cross an edge).
    const auto inside = [&](double& x, double& y) {
        for (;;) {
            const double fx = uni(rng), fy = uni(rng);
            if (fx > 0.01 && fx < 0.99 && fy > 0.01 && fy < 0.99 && std::fabs(fx - fy) > 0.01) {
                x = static_cast<double>(rng() % 80) + fx;
                y = static_cast<double>(rng() % 80) + fy;
                return;
            }
        }
    };
    RayBatch world, local;
    std::vector<int> copy;
    for (int k = 0; k < 5000; ++k) {
        const int i = static_cast<int>(rng() % n), j = static_cast<int>(rng() % n);
        double x = 0, y = 0;
        inside(x, y);
        world.push_back({100.0 * i + x, 100.0 * j + y, 10.0}, {0, 0, -1});
        local.push_back({x, y, 10.0}, {0, 0, -1});
        copy.push_back(j * n + i);
    }
    const std::vector<BackendKind> kinds = test::instancing_backends();
    const HitBatch hl = single->intersect(local, pool);
    for (const BackendKind kind : kinds) {
        const auto backend = kind == BackendKind::bvh ? nullptr : make_backend(kind, g, pool);
        const Backend& b = backend ? *backend : *bvh;
        const HitBatch hw = b.intersect(world, pool);
        for (std::size_t k = 0; k < world.size(); ++k) {
            ASSERT_TRUE(hw.hit(k) && hl.hit(k)) << to_string(kind) << " " << k;
            const auto c = static_cast<std::uint32_t>(copy[k]);
            EXPECT_EQ(hw.face[k], c * 12800u + hl.face[k]) << to_string(kind) << " " << k;
            EXPECT_NEAR(hw.t[k], 10.0 - 0.5 * ((c % n + c / n) % 3), 1e-5) << k;
        }
        // Between the tiles there is nothing.
        RayBatch gaps;
        gaps.push_back({90.0, 50.0, 10.0}, {0, 0, -1});
        EXPECT_FALSE(b.intersect(gaps, pool).hit(0)) << to_string(kind);
    }
}

}  // namespace
}  // namespace beamtrace
