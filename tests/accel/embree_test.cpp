// The Embree backend's own contract: the option is refused clearly without Embree, barycentrics
// and ranges follow ray_triangle.hpp's convention, and shared and copied vertex buffers agree.
#include <gtest/gtest.h>

#include <random>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "harness/embree_limit.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(EmbreeBackend, ParseBackendKindSaysWhetherEmbreeIsBuilt) {
    if (embree_available()) {
        EXPECT_EQ(parse_backend_kind("embree"), BackendKind::embree);
        EXPECT_EQ(to_string(BackendKind::embree), "embree");
    } else {
        try {
            (void)parse_backend_kind("embree");
            ADD_FAILURE() << "embree accepted without Embree";
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("built without Embree"), std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW((void)parse_backend_kind("optix"), ConfigError);
}

RayBatch sphere_rays(std::size_t n, unsigned seed) {
    RayBatch rays;
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3d o = normalize(Vec3d{g(rng), g(rng), g(rng)}) * 5.0;
        rays.push_back(o, normalize(Vec3d{g(rng), g(rng), g(rng)} * 0.8 - o));
    }
    return rays;
}

TEST(EmbreeBackend, BarycentricsAndRangeMatchOurConvention) {
    if (!embree_available()) {
        BEAMTRACE_SKIP_OR_FAIL("built without Embree");
    }
    const TriangleMesh sphere = test::make_icosphere(3, 2.0f);
    ThreadPool pool(2);
    const RayBatch rays = sphere_rays(3000, 17);
    const HitBatch want = make_backend(BackendKind::brute, sphere, pool)->intersect(rays, pool);
    const HitBatch got = make_backend(BackendKind::embree, sphere, pool)->intersect(rays, pool);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(got.hit(i), want.hit(i)) << i;
        if (!got.hit(i)) {
            continue;
        }
        ++hits;
        EXPECT_NEAR(got.t[i], want.t[i], 1e-5f * want.t[i]) << i;
        if (got.face[i] != want.face[i]) {
            continue;  // an edge: same range, another face
        }
        EXPECT_NEAR(got.u[i], want.u[i], 1e-4f) << i;
        EXPECT_NEAR(got.v[i], want.v[i], 1e-4f) << i;
        // The point is (1-u-v) V0 + u V1 + v V2.
        const Face& f = sphere.faces[got.face[i]];
        const Vec3d a(sphere.vertices[f[0]]), b(sphere.vertices[f[1]]), c(sphere.vertices[f[2]]);
        const double u = got.u[i], v = got.v[i];
        const Vec3d p = a * (1.0 - u - v) + b * u + c * v;
        const Vec3d q = rays.origin(i) + rays.direction(i) * double(got.t[i]);
        EXPECT_LT(length(p - q), 1e-5) << i;
    }
    EXPECT_GT(hits, rays.size() / 2);
}

TEST(EmbreeBackend, SharedAndCopiedVertexBuffersAgreeAndTminTmaxApply) {
    if (!embree_available()) {
        BEAMTRACE_SKIP_OR_FAIL("built without Embree");
    }
    TriangleMesh tight = test::make_icosphere(3, 2.0f);
    tight.vertices.shrink_to_fit();  // no slack: the backend copies the vertices once
    TriangleMesh slack = tight;
    slack.vertices.reserve(slack.vertices.size() + 1);  // slack: the backend shares them
    ThreadPool pool(2);
    RayBatch rays = sphere_rays(2000, 23);
    for (std::size_t i = 0; i < rays.size(); i += 3) {
        rays.tmin[i] = 4.0;  // skips the first hit of most rays
    }
    for (std::size_t i = 1; i < rays.size(); i += 3) {
        rays.tmax[i] = 3.5;  // most of these end before the sphere
    }
    const HitBatch want = make_backend(BackendKind::brute, tight, pool)->intersect(rays, pool);
    for (const TriangleMesh* mesh : {&tight, &slack}) {
        const auto embree = make_backend(BackendKind::embree, *mesh, pool);
        const HitBatch got = embree->intersect(rays, pool);
        std::vector<std::uint8_t> occ;
        embree->occluded(rays, 0, rays.size(), occ, pool);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(got.hit(i), want.hit(i)) << i;
            ASSERT_EQ(occ[i] != 0, want.hit(i)) << i;
            if (want.hit(i)) {
                EXPECT_NEAR(got.t[i], want.t[i], 1e-5f * want.t[i]) << i;
            }
        }
    }
}

TEST(EmbreeBackend, PartialRangeLeavesOtherSlotsAlone) {
    if (!embree_available()) {
        BEAMTRACE_SKIP_OR_FAIL("built without Embree");
    }
    const TriangleMesh sphere = test::make_icosphere(2, 2.0f);
    ThreadPool pool(2);
    const RayBatch rays = sphere_rays(100, 29);
    const auto embree = make_backend(BackendKind::embree, sphere, pool);
    HitBatch hits;
    hits.resize(rays.size());
    embree->intersect(rays, 40, 60, hits, pool);
    const HitBatch all = embree->intersect(rays, pool);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (i >= 40 && i < 60) {
            EXPECT_EQ(hits.face[i], all.face[i]) << i;
        } else {
            EXPECT_EQ(hits.face[i], kNoFace) << i;
        }
    }
}

TEST(EmbreeBackend, PacketsGiveTheSameHitsWhateverTheSplitAndThreads) {
#ifdef BEAMTRACE_HAVE_EMBREE
    const TriangleMesh sphere = test::make_icosphere(4, 2.0f);
    const RayBatch rays = sphere_rays(5003, 23);
    ThreadPool one(1), three(3);
    const auto backend = make_backend(BackendKind::embree, sphere, one);
    const HitBatch whole = backend->intersect(rays, one);
    HitBatch split;
    split.resize(rays.size());
    // Pieces that cut packets of 16 in the middle, traced on another pool.
    for (const auto& [b, e] : std::vector<std::pair<std::size_t, std::size_t>>{
             {0, 7}, {7, 1237}, {1237, 1238}, {1238, 4999}, {4999, 5003}}) {
        backend->intersect(rays, b, e, split, three);
    }
    EXPECT_EQ(whole.t, split.t);
    EXPECT_EQ(whole.face, split.face);
    EXPECT_EQ(whole.u, split.u);
    EXPECT_EQ(whole.v, split.v);
    // The same faces as a plain rtcIntersect1 loop, but for rays aimed exactly at an edge.
    const EmbreeLimit limit(sphere, 1);
    std::vector<std::uint32_t> face;
    limit.trace(rays, EmbreeCall::single, face, one);
    std::size_t hits = 0, same = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(face[i] == kNoFace, !whole.hit(i)) << "ray " << i;
        hits += whole.hit(i) ? 1 : 0;
        same += whole.hit(i) && face[i] == whole.face[i] ? 1 : 0;
    }
    EXPECT_GT(hits, rays.size() / 2);
    EXPECT_GE(same + 2, hits);
#else
    BEAMTRACE_SKIP_OR_FAIL("built without Embree");
#endif
}

TEST(EmbreeBackend, IsTheDefaultOfSurveysWhenBuilt) {
    EXPECT_EQ(SurveyRunConfig{}.backend,
              embree_available() ? BackendKind::embree : BackendKind::bvh);
}

}  // namespace
}  // namespace beamtrace
