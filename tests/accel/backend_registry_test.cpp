// The backend table: names parse back to their entries, built/available agree with this build,
// and every usable backend made through the table agrees with brute force.
#include "beamtrace/accel/backend_registry.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(BackendRegistry, EveryKindHasOneEntryWhoseNameParsesBack) {
    std::set<BackendKind> kinds;
    std::set<std::string_view> names;
    for (const BackendEntry& e : backend_registry()) {
        EXPECT_TRUE(kinds.insert(e.kind).second) << e.name;
        EXPECT_TRUE(names.insert(e.name).second) << e.name;
        EXPECT_EQ(&backend_entry(e.kind), &e);
        EXPECT_EQ(find_backend(e.name), &e);
        EXPECT_EQ(to_string(e.kind), e.name);
        if (e.usable()) {
            EXPECT_EQ(parse_backend_kind(e.name), e.kind);
        } else {
            EXPECT_THROW((void)parse_backend_kind(e.name), ConfigError) << e.name;
        }
        EXPECT_GT(e.traits.preferred_batch_rays, 0u) << e.name;
        EXPECT_FALSE(e.summary.empty());
    }
    for (const BackendKind k :
         {BackendKind::brute, BackendKind::kdtree, BackendKind::bvh, BackendKind::embree}) {
        EXPECT_EQ(kinds.count(k), 1u) << static_cast<int>(k);
    }
    EXPECT_EQ(find_backend("optix"), nullptr);
}

TEST(BackendRegistry, UnknownNameListsEveryBuiltBackend) {
    try {
        (void)parse_backend_kind("optix");
        FAIL() << "optix parsed";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("unknown backend 'optix'"), std::string::npos) << msg;
        for (const BackendEntry& b : backend_registry()) {
            EXPECT_EQ(msg.find(std::string(b.name)) != std::string::npos, b.built) << msg;
        }
    }
    std::string expected;
    for (const BackendEntry& b : backend_registry()) {
        if (b.built) {
            expected += (expected.empty() ? "" : " | ") + std::string(b.name);
        }
    }
    EXPECT_EQ(backend_choices(), expected);
}

TEST(BackendRegistry, BuiltMatchesThisBuild) {
    for (const BackendEntry& e : backend_registry()) {
        EXPECT_EQ(e.built, e.make_for_mesh != nullptr) << e.name;
        EXPECT_EQ(e.built, e.make_for_scene != nullptr) << e.name;
        if (!e.built) {
            EXPECT_FALSE(e.how_to_build.empty()) << e.name;
        }
    }
    EXPECT_EQ(backend_entry(BackendKind::embree).built, embree_available());
    EXPECT_TRUE(backend_entry(BackendKind::bvh).traits.instances_natively);
    EXPECT_FALSE(backend_entry(BackendKind::brute).traits.instances_natively);
    EXPECT_TRUE(backend_entry(default_backend_kind()).usable());
    const auto usable = usable_backends();
    EXPECT_NE(std::find(usable.begin(), usable.end(), default_backend_kind()), usable.end());
}

TEST(BackendRegistry, EveryUsableBackendAgreesWithBruteForceThroughTheTable) {
    const TriangleMesh sphere = test::make_icosphere(2, 1.0f);
    RayBatch rays;
    for (int i = 0; i < 400; ++i) {
        const double a = 0.05 * i, z = -1.2 + 0.006 * i;
        rays.push_back({3.0 * std::cos(a), 3.0 * std::sin(a), z},
                       {-std::cos(a), -std::sin(a), 0.1});
    }
    ThreadPool pool(2);
    const HitBatch want = make_backend(BackendKind::brute, sphere, pool)->intersect(rays, pool);
    std::size_t hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += want.hit(i) ? 1 : 0;
    }
    ASSERT_GT(hits, rays.size() / 4);
    ASSERT_LT(hits, rays.size());
    for (const BackendEntry& e : backend_registry()) {
        if (!test::with_backend(e)) {
            continue;
        }
        const auto backend = e.make_for_mesh(sphere, pool, {});
        EXPECT_EQ(backend->kind(), e.kind);
        EXPECT_EQ(&backend->traits(), &e.traits);
        const HitBatch got = backend->intersect(rays, pool);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(got.hit(i), want.hit(i)) << e.name << " ray " << i;
            if (want.hit(i)) {
                EXPECT_NEAR(got.t[i], want.t[i], 1e-5f * want.t[i]) << e.name << " ray " << i;
            }
        }
    }
}

}  // namespace
}  // namespace beamtrace
