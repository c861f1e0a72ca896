// One origin for the whole scene (docs/scene-file.md, "Origin"): origin_m places every part
// given in local metres (meshes, planes, spheres) and the survey's platform, rasters keep their
// absolute (projected) coordinates, and the outputs are in the origin's frame: a mesh scene with a
// UTM origin writes UTM coordinates, LAS offsets near the origin and the scene's CRS.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "beamtrace/io/las_crs.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kEast = 500000.0, kNorth = 5400000.0, kUp = 100.0;

/// A 100 m quad at local height `z_m` centred on the local origin.
std::string quad_obj(double z_m) {
    const std::string z = std::to_string(z_m);
    return "v -50 -50 " + z + "\nv 50 -50 " + z + "\nv 50 50 " + z + "\nv -50 50 " + z +
           "\nf 1 2 3\nf 1 3 4\n";
}

/// A 3 x 3 nadir pinhole 50 m above the local origin (pixel rays 10 deg apart).
const std::string kSurvey =
    "scene: scene.yaml\n"
    "scanner: {type: pinhole, width: 3, height: 3, hfov_deg: 20, vfov_deg: 20}\n"
    "platform: {type: static, position_m: [0, 0, 50], rotate_deg: [0, -90, 0]}\n"
    "output: {trajectory_rate_hz: 0}\n";

TEST(SceneOrigin, MeshSceneWithUtmOriginWritesUtmCoordinates) {
    test::TempDir dir;
    test::write_file(dir / "quad.obj", quad_obj(0.0));
    test::write_file(dir / "scene.yaml",
                     "origin_m: [500000, 5400000, 100]\ncrs: EPSG:32632\nparts:\n"
                     "  - mesh: quad.obj\n");
    const std::vector<LasPoint> points = test::run_and_read(kSurvey, dir, 2);
    ASSERT_EQ(points.size(), 9u);
    // Pixel (u, v) of the pinhole hits the quad 50 m below at tan(10 deg) x 50 = 8.816 m steps:
    // UTM coordinates = origin + local.
    const double step = 50.0 * std::tan(10.0 * std::acos(-1.0) / 180.0);
    double sx = 0, sy = 0;
    for (const LasPoint& p : points) {
        EXPECT_NEAR(p.z, kUp, 1e-3);
        const double dx = p.x - kEast, dy = p.y - kNorth;
        EXPECT_NEAR(std::abs(dx), std::round(std::abs(dx) / step) * step, 2e-3) << dx;
        EXPECT_NEAR(std::abs(dy), std::round(std::abs(dy) / step) * step, 2e-3) << dy;
        EXPECT_LE(std::abs(dx), step + 2e-3);
        EXPECT_LE(std::abs(dy), step + 2e-3);
        sx += dx;
        sy += dy;
    }
    EXPECT_NEAR(sx, 0.0, 1e-2);  // symmetric about the origin
    EXPECT_NEAR(sy, 0.0, 1e-2);
    // The LAS header: offsets at the origin (millimetres keep their precision), the extent, the
    // scene's CRS as an OGC WKT record.
    LasReader reader(dir / "out" / "points.las");
    const LasHeader& h = reader.header();
    EXPECT_NEAR(h.offset.x, kEast, 1000.0);
    EXPECT_NEAR(h.offset.y, kNorth, 1000.0);
    EXPECT_EQ(h.scale.x, 0.001);
    EXPECT_NEAR(h.min.x, kEast - step, 2e-3);
    EXPECT_NEAR(h.max.y, kNorth + step, 2e-3);
    const LasFileCrs crs = las_file_crs(h, reader.vlrs());
    EXPECT_EQ(crs.source, LasCrsSource::wkt);
    EXPECT_NE(crs.crs.wkt.find("UTM zone 32N"), std::string::npos) << crs.crs.wkt;
}

TEST(SceneOrigin, RastersKeepTheirAbsoluteCoordinatesBesideLocalMeshes) {
    // A flat DEM at 100 m above sea level given in UTM (its lower-left corner 200 m south-west of
    // the origin) and a 10 m high roof (a local mesh): both land in one frame.
    test::TempDir dir;
    test::write_file(dir / "dem.asc",
                     "ncols 5\nnrows 5\nxllcorner 499800\nyllcorner 5399800\ncellsize 100\n"
                     "100 100 100 100 100\n100 100 100 100 100\n100 100 100 100 100\n"
                     "100 100 100 100 100\n100 100 100 100 100\n");
    test::write_file(dir / "roof.obj",
                     "v -3 -3 10\nv 3 -3 10\nv 3 3 10\nv -3 3 10\nf 1 2 3\nf 1 3 4\n");
    test::write_file(dir / "scene.yaml",
                     "origin_m: [500000, 5400000, 100]\nparts:\n  - raster: dem.asc\n"
                     "  - mesh: roof.obj\n    part_id: 9\n");
    const std::vector<LasPoint> points = test::run_and_read(kSurvey, dir, 2);
    ASSERT_EQ(points.size(), 9u);
    int roof = 0;
    for (const LasPoint& p : points) {
        // The centre ray meets the roof 40 m below the platform (UTM height 110 m); the others
        // pass beside it (8.8 m off at the ground, 7 m at the roof) onto the DEM's 100 m.
        const bool on_roof = p.point_source_id == 9;
        roof += on_roof ? 1 : 0;
        EXPECT_NEAR(p.z, on_roof ? kUp + 10.0 : kUp, 1e-3);
        EXPECT_NEAR(p.x, kEast, 9.0);
        EXPECT_NEAR(p.y, kNorth, 9.0);
    }
    EXPECT_EQ(roof, 1);
}

}  // namespace
}  // namespace beamtrace
