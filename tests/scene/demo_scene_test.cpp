#include "beamtrace/scene/demo_scene.hpp"

#include <gtest/gtest.h>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"

namespace beamtrace {
namespace {

TEST(DemoScene, HasTerrainVehiclesAndOccluder) {
    const Scene s = make_demo_scene();
    ASSERT_EQ(s.parts.size(), 5u);
    EXPECT_EQ(s.parts[0].name, "terrain");
    EXPECT_EQ(s.parts[0].face_count, 2u * 200u * 200u);
    EXPECT_EQ(s.parts[4].name, "occluder");
    EXPECT_EQ(s.parts[4].face_count, 2u);
    EXPECT_EQ(s.parts[4].first_face + 2, s.triangle_count());
    EXPECT_EQ(s.part_of_face(0), 0u);
    EXPECT_EQ(s.part_of_face(s.parts[2].first_face), 2u);
    EXPECT_EQ(s.part_of_face(static_cast<std::uint32_t>(s.triangle_count() - 1)), 4u);
    // Terrain vertices follow the height function.
    const Vec3f v = s.geometry.meshes[0].vertices[12345];
    EXPECT_NEAR(v.z, demo_terrain_height(v.x, v.y), 1e-4);
}

TEST(DemoScene, DefaultViewSeesVehicleAndOccluder) {
    const Scene s = make_demo_scene();
    ThreadPool pool(2);
    const auto bvh = make_backend(BackendKind::bvh, s.geometry, pool);
    const HitBatch hits = bvh->intersect(cast_rays_pinhole(demo_sensor()), pool);
    std::vector<std::size_t> per_part(s.parts.size(), 0);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (hits.hit(i)) {
            ++per_part[s.part_of_face(hits.face[i])];
        }
    }
    EXPECT_GT(per_part[0], 1000u) << "terrain";
    EXPECT_GT(per_part[1], 200u) << "vehicle 1, partly behind the occluder";
    EXPECT_GT(per_part[2] + per_part[3], 200u) << "vehicles 2 and 3";
    EXPECT_GT(per_part[4], 100u) << "occluder";
}

}  // namespace
}  // namespace beamtrace
