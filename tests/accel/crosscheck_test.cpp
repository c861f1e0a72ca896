// Every backend against brute force on the same rays: real meshes, random and adversarial rays.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/geometry/moller_trumbore.hpp"
#include "beamtrace/scene/mesh_loader.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// Rays from a sphere around the mesh aimed at random points of its bounding box (most hit),
/// plus 10 % in random directions (many miss).
RayBatch random_rays(const TriangleMesh& mesh, std::size_t n, unsigned seed) {
    return test::rays_toward(mesh.bounds(), n, seed, 10);
}

/// Rays aimed exactly at every vertex and at edge points of the mesh.
RayBatch vertex_and_edge_rays(const TriangleMesh& mesh, std::size_t max_rays, unsigned seed) {
    const Aabb b = mesh.bounds();
    const Vec3d c(b.center());
    const double radius = 1.5 * length(Vec3d(b.extent()));
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    RayBatch rays;
    const std::size_t step = std::max<std::size_t>(1, mesh.faces.size() / max_rays);
    for (std::size_t f = 0; f < mesh.faces.size() && rays.size() < max_rays; f += step) {
        const Face& face = mesh.faces[f];
        const Vec3d a(mesh.vertices[face[0]]), bb(mesh.vertices[face[1]]);
        const Vec3d target = (f % 2 == 0) ? a : a + (bb - a) * uni(rng);
        const Vec3d o = c + normalize(Vec3d{g(rng), g(rng), g(rng)}) * radius;
        rays.push_back(o, normalize(target - o));
    }
    return rays;
}

struct NamedBackend {
    BackendKind kind;
    BackendConfig config;
    const char* name;
};

/// Every accelerated backend and build rule set.
std::vector<NamedBackend> accelerated_backends() {
    BackendConfig report;
    report.kdtree = KdTreeBuildConfig::report();
    std::vector<NamedBackend> all{{BackendKind::kdtree, {}, "kdtree"},
                                  {BackendKind::kdtree, report, "kdtree-report-rules"},
                                  {BackendKind::bvh, {}, "bvh"}};
    if (embree_available()) {
        all.push_back({BackendKind::embree, {}, "embree"});
    }
    return all;
}

/// True when the point at range t along ray i lies on face `face` (within float rounding): a
/// legitimate hit of a ray that grazes an edge or vertex, which a non-watertight test may report
/// although the watertight test gives the ray to a neighbour.
bool on_face(const TriangleMesh& mesh, std::uint32_t face, const RayBatch& rays, std::size_t i,
             double t) {
    const Face& f = mesh.faces[face];
    const Vec3d a(mesh.vertices[f[0]]), b(mesh.vertices[f[1]]), c(mesh.vertices[f[2]]);
    const Vec3d q = rays.origin(i) + rays.direction(i) * t;
    const Vec3d n = cross(b - a, c - a);
    const double nn = dot(n, n);
    const double tol = 1e-5 * std::max(1.0, t);
    if (std::abs(dot(q - a, n)) > tol * std::sqrt(nn)) {
        return false;
    }
    // Barycentrics of q's projection; slack 1e-3 (float origins move the point by ~1e-7 of the
    // range, a sizeable fraction of a millimetre-sized triangle's barycentrics).
    const double u = dot(cross(q - a, c - a), n) / nn;
    const double v = dot(cross(b - a, q - a), n) / nn;
    return u >= -1e-3 && v >= -1e-3 && u + v <= 1.0 + 1e-3;
}

/// Our backends share one watertight test and agree exactly with brute force. Embree's
/// triangle test is not that test: on rays aimed exactly at vertices and edges it may give a
/// grazing hit on a neighbouring face (a point of that face within float rounding, nearer than
/// the oracle's), which is counted and limited separately.
bool shares_watertight_test(BackendKind kind) {
    return kind != BackendKind::embree;
}

/// `edge_rays`: rays aimed exactly at vertices and edges, where Embree may differ (see above).
void expect_agreement(const TriangleMesh& mesh, const RayBatch& rays, const char* what,
                      bool edge_rays = false) {
    ThreadPool pool(0);
    const auto brute = make_backend(BackendKind::brute, mesh, pool);
    const HitBatch oracle = brute->intersect(rays, pool);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += oracle.hit(i) ? 1 : 0;
    }
    EXPECT_GT(hits, rays.size() / 10) << what << ": the test rays should hit something";
    for (const auto& [kind, config, name] : accelerated_backends()) {
        const auto backend = make_backend(kind, mesh, pool, config);
        const HitBatch got = backend->intersect(rays, pool);
        std::size_t bad = 0, grazing = 0, slipped = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const bool same_face = got.face[i] == oracle.face[i];
            const bool same_range =
                oracle.hit(i) && got.hit(i) &&
                std::abs(double(got.t[i]) - double(oracle.t[i])) <= 1e-6 * double(oracle.t[i]);
            if (!same_face && !same_range && !shares_watertight_test(kind) && got.hit(i) &&
                (!oracle.hit(i) || got.t[i] < oracle.t[i]) &&
                on_face(mesh, got.face[i], rays, i, double(got.t[i]))) {
                ++grazing;
                continue;
            }
            if (!same_face && !same_range && !shares_watertight_test(kind) && oracle.hit(i) &&
                (!got.hit(i) || got.t[i] > oracle.t[i]) &&
                std::min({double(oracle.u[i]), double(oracle.v[i]),
                          1.0 - double(oracle.u[i]) - double(oracle.v[i])}) < 1e-3) {
                ++slipped;  // through an edge or vertex the oracle's hit lies on
                continue;
            }
            if (!same_face && !same_range) {
                if (++bad <= 5 && shares_watertight_test(kind)) {
                    ADD_FAILURE() << what << " " << name << " ray " << i << ": face " << got.face[i]
                                  << " t " << got.t[i] << " vs brute face " << oracle.face[i]
                                  << " t " << oracle.t[i];
                }
            }
        }
        if (shares_watertight_test(kind) || !edge_rays) {
            EXPECT_EQ(bad, 0u) << what << " " << name;
            EXPECT_EQ(grazing + slipped, 0u) << what << " " << name;
        } else {
            // Edge rays that neither graze nor slip by the tests above (a wider grazing angle
            // than their tolerance): at most 1 in 1000 (3 on the small sanitizer runs). Random
            // rays must agree exactly.
            EXPECT_LE(bad, std::max<std::size_t>(3, rays.size() / 1000)) << what << " " << name;
        }
        // Grazing and slipping only on rays aimed at edges and vertices, and rarely there.
        EXPECT_LE(grazing + slipped, rays.size() / 50) << what << " " << name;
        if (grazing + slipped > 0) {
            std::printf(
                "  %s %s: of %zu rays, %zu graze a neighbouring face, %zu slip through "
                "an edge or vertex\n",
                what, name, rays.size(), grazing, slipped);
        }
        // Occlusion agrees with the nearest-hit query.
        std::vector<std::uint8_t> occ;
        backend->occluded(rays, 0, rays.size(), occ, pool);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(occ[i] != 0, got.hit(i)) << what << " " << name << " ray " << i;
        }
    }
}

TEST(CrossCheck, BunnyRandomRays) {
    const auto path = test::shared_data("meshes/small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    expect_agreement(mesh, random_rays(mesh, test::heavy_scale(60000), 1), "bunny");
}

TEST(CrossCheck, TerrainRandomRays) {
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    expect_agreement(mesh, random_rays(mesh, test::heavy_scale(60000), 2), "terrain");
}

TEST(CrossCheck, BunnyVertexAndEdgeRays) {
    const auto path = test::shared_data("meshes/small/stanford-bunny.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    expect_agreement(mesh, vertex_and_edge_rays(mesh, test::heavy_scale(10000), 3),
                     "bunny-vertices", true);
}

TEST(CrossCheck, TerrainVertexAndEdgeRays) {
    const auto path = test::shared_data("meshes/terrain/dem_hd_sub_heightfield.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    expect_agreement(mesh, vertex_and_edge_rays(mesh, test::heavy_scale(10000), 4),
                     "terrain-vertices", true);
}

/// Rays from inside a closed mesh through its vertices and edges must hit: no leaks.
void expect_no_leaks(const TriangleMesh& mesh, const Vec3d& inside, const char* what) {
    RayBatch rays;
    for (const auto& v : mesh.vertices) {
        rays.push_back(inside, normalize(Vec3d(v) - inside));
    }
    for (const auto& f : mesh.faces) {
        for (int k = 0; k < 3; ++k) {
            const Vec3d a(mesh.vertices[f[static_cast<std::size_t>(k)]]);
            const Vec3d b(mesh.vertices[f[static_cast<std::size_t>((k + 1) % 3)]]);
            rays.push_back(inside, normalize((a + b) * 0.5 - inside));
        }
    }
    ThreadPool pool(0);
    auto backends = accelerated_backends();
    backends.push_back({BackendKind::brute, {}, "brute"});
    for (const auto& [kind, config, name] : backends) {
        const auto backend = make_backend(kind, mesh, pool, config);
        const HitBatch hits = backend->intersect(rays, pool);
        std::size_t leaks = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            leaks += hits.hit(i) ? 0 : 1;
        }
        EXPECT_EQ(leaks, 0u) << what << " " << name << ": " << leaks << " of " << rays.size()
                             << " rays escaped";
    }
}

TEST(CrossCheck, NoLeaksThroughIcosphereVerticesAndEdges) {
    expect_no_leaks(test::make_icosphere(4, 3.0f), {0.0, 0.0, 0.0}, "icosphere");
    expect_no_leaks(test::make_icosphere(3, 1.0f), {0.1, -0.2, 0.05}, "icosphere-offset");
}

TEST(CrossCheck, NoLeaksThroughSpotVerticesAndEdges) {
    const auto path = test::shared_data("meshes/small/spot.obj");
    BEAMTRACE_REQUIRE_FILE(path);
    const TriangleMesh mesh = load_mesh(path);
    // An interior point: halfway between the first two hits of a ray through the body.
    ThreadPool pool(1);
    const auto bvh = make_backend(BackendKind::bvh, mesh, pool);
    RayBatch probe;
    const Vec3d c(mesh.bounds().center());
    probe.push_back(c + Vec3d{0, 0, 10}, {0, 0, -1});
    AllHits all;
    bvh->intersect_all(probe, Facing::both, all, pool);
    ASSERT_GE(all.count(0), 2u);
    ASSERT_TRUE(all.front[0]);
    const double mid = 0.5 * (double(all.t[0]) + double(all.t[1]));
    expect_no_leaks(mesh, c + Vec3d{0, 0, 10} + Vec3d{0, 0, -1} * mid, "spot");
}

TEST(CrossCheck, AxisAlignedRaysThroughGridVerticesAndEdges) {
    // Exactly representable vertices and rays exactly through them: the hardest case for
    // slab tests (origin on box planes, zero direction components) and for the k-d tree (split
    // planes through the ray).
    const TriangleMesh grid = test::make_grid(32);
    RayBatch rays;
    for (int j = 0; j <= 64; ++j) {
        for (int i = 0; i <= 64; ++i) {
            const double x = 0.5 * i, y = 0.5 * j;
            rays.push_back({x, y, 10.0}, {0, 0, -1});
            rays.push_back({x, y, -10.0}, {0, 0, 1});
        }
    }
    ThreadPool pool(2);
    auto backends = accelerated_backends();
    backends.push_back({BackendKind::brute, {}, "brute"});
    for (const auto& [kind, config, name] : backends) {
        const auto backend = make_backend(kind, grid, pool, config);
        const HitBatch hits = backend->intersect(rays, pool);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const double x = rays.ox[i], y = rays.oy[i];
            if (!shares_watertight_test(kind) && (x == 32.0 || y == 32.0 || x == 0.0 || y == 0.0)) {
                // Embree's edge test is not closed on every side: rays exactly along the outer
                // boundary of an open mesh may miss it (a ray off the mesh by any amount does).
                continue;
            }
            ASSERT_TRUE(hits.hit(i)) << name << " ray " << i << " leaked";
            EXPECT_EQ(hits.t[i], 10.0f);
        }
    }
    // Embree against brute force on the interior rays only (see above).
    RayBatch interior;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const double x = rays.ox[i], y = rays.oy[i];
        if (x > 0.0 && x < 32.0 && y > 0.0 && y < 32.0) {
            interior.push_back(rays.origin(i), rays.direction(i));
        }
    }
    expect_agreement(grid, interior, "grid", true);
}

TEST(CrossCheck, AllHitsMatchBruteForceAndMollerTrumbore) {
    const TriangleMesh sphere = test::make_icosphere(3, 2.0f);
    ThreadPool pool(2);
    RayBatch rays;
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const Vec3d o = normalize(Vec3d{g(rng), g(rng), g(rng)}) * 5.0;
        rays.push_back(o, normalize(Vec3d{g(rng), g(rng), g(rng)} * 0.8 - o));
    }
    AllHits ref;
    make_backend(BackendKind::brute, sphere, pool)->intersect_all(rays, Facing::both, ref, pool);
    std::vector<BackendKind> kinds{BackendKind::kdtree, BackendKind::bvh};
    if (embree_available()) {
        kinds.push_back(BackendKind::embree);
    }
    for (BackendKind kind : kinds) {
        for (Facing facing : {Facing::front, Facing::back, Facing::both}) {
            AllHits got;
            make_backend(kind, sphere, pool)->intersect_all(rays, facing, got, pool);
            for (std::size_t i = 0; i < rays.size(); ++i) {
                std::vector<std::uint32_t> expect;
                for (std::size_t k = ref.offsets[i]; k < ref.offsets[i + 1]; ++k) {
                    const bool front = ref.front[k] != 0;
                    if (facing == Facing::both || (facing == Facing::front) == front) {
                        expect.push_back(ref.face[k]);
                    }
                }
                std::vector<std::uint32_t> faces(
                    got.face.begin() + static_cast<long>(got.offsets[i]),
                    got.face.begin() + static_cast<long>(got.offsets[i + 1]));
                ASSERT_EQ(faces, expect) << to_string(kind) << " ray " << i;
                if (facing == Facing::both) {
                    const auto mt =
                        ray_intersect_all(sphere, rays.origin(i), rays.direction(i), Facing::both);
                    EXPECT_EQ(mt.size(), faces.size()) << "ray " << i;
                }
            }
        }
    }
}

TEST(CrossCheck, ResultsDoNotDependOnThreadCount) {
    const TriangleMesh sphere = test::make_icosphere(3, 2.0f);
    RayBatch rays;
    std::mt19937 rng(9);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < 20000; ++i) {
        const Vec3d o = normalize(Vec3d{g(rng), g(rng), g(rng)}) * 5.0;
        rays.push_back(o, normalize(Vec3d{g(rng), g(rng), g(rng)} - o));
    }
    ThreadPool one(1), four(4);
    std::vector<BackendKind> kinds{BackendKind::kdtree, BackendKind::bvh};
    if (embree_available()) {
        kinds.push_back(BackendKind::embree);
    }
    for (BackendKind kind : kinds) {
        const HitBatch a = make_backend(kind, sphere, one)->intersect(rays, one);
        const HitBatch b = make_backend(kind, sphere, four)->intersect(rays, four);
        EXPECT_EQ(a.t, b.t);
        EXPECT_EQ(a.face, b.face);
        EXPECT_EQ(a.u, b.u);
    }
}

}  // namespace
}  // namespace beamtrace
