// points_box(): the box the default view frames holds most of the points, not the far few.
#include "beamtrace/heightfield/data_framing.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "beamtrace/io/las_writer.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// 20 000 points uniform in [0, 100] x [0, 50] and 100 (0.5 %) far away, in time order mixed.
std::vector<LasPoint> near_and_far() {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<LasPoint> points;
    for (int i = 0; i < 20100; ++i) {
        LasPoint p;
        const bool far = i % 201 == 200;
        p.x = far ? 1000.0 + 100.0 * u(rng) : 100.0 * u(rng);
        p.y = far ? -2000.0 : 50.0 * u(rng);
        p.z = u(rng);
        p.return_number = p.number_of_returns = 1;
        points.push_back(p);
    }
    return points;
}

std::filesystem::path write(const std::filesystem::path& path, LasCompression compression) {
    LasWriterConfig config;
    config.point_format = 6;
    config.scale = {0.01, 0.01, 0.01};
    config.compression = compression;
    config.laz_chunk_size = 1000;
    LasWriter writer(path, config);
    writer.write(near_and_far());
    writer.close();
    return path;
}

TEST(DataFraming, TheBoxOfMostPointsLeavesTheFarFewOut) {
    test::TempDir dir;
    for (const auto compression : {LasCompression::none, LasCompression::laz}) {
        const auto path =
            write(dir / (compression == LasCompression::laz ? "a.laz" : "a.las"), compression);
        const std::vector<std::filesystem::path> inputs = {path};
        const LasSourceSet sources(inputs);
        EXPECT_GT(sources.max().x, 1000.0);  // the header box holds the far points
        EXPECT_LT(sources.min().y, -1999.0);
        const PointsBox box = points_box(sources);
        EXPECT_GT(box.samples, 4000u);
        // 2 % and 98 % of a uniform [0, 100] x [0, 50] (the far 0.5 % shift them a little),
        // then 10 % of the size on each side, within the header box: about [0, 108] x
        // [-3.8, 50] (the far points lie at x > 1000 and y = -2000).
        EXPECT_EQ(box.lo.x, sources.min().x);
        EXPECT_NEAR(box.hi.x, 108.0, 1.0);
        EXPECT_NEAR(box.lo.y, -3.8, 1.0);
        EXPECT_EQ(box.hi.y, sources.max().y);
        EXPECT_EQ(box.lo.z, sources.min().z);
        EXPECT_EQ(box.hi.z, sources.max().z);
    }
}

TEST(DataFraming, PointsThatFillTheirHeaderBoxAreFramedWhole) {
    test::TempDir dir;
    std::vector<LasPoint> points = near_and_far();
    std::erase_if(points, [](const LasPoint& p) { return p.x > 100.0; });
    const auto path = test::write_test_las(dir / "uniform.las", points, 6);
    const std::vector<std::filesystem::path> inputs = {path};
    const LasSourceSet sources(inputs);
    const PointsBox box = points_box(sources);
    EXPECT_GT(box.samples, 4000u);
    EXPECT_EQ(box.lo.x, sources.min().x);
    EXPECT_EQ(box.hi.x, sources.max().x);
    EXPECT_EQ(box.lo.y, sources.min().y);
    EXPECT_EQ(box.hi.y, sources.max().y);
}

TEST(DataFraming, NoPointsGiveTheHeaderBox) {
    test::TempDir dir;
    LasWriterConfig config;
    LasWriter writer(dir / "empty.las", config);
    writer.close();
    const std::vector<std::filesystem::path> inputs = {dir / "empty.las"};
    const LasSourceSet sources(inputs);
    const PointsBox box = points_box(sources);
    EXPECT_EQ(box.samples, 0u);
    EXPECT_EQ(box.lo.x, sources.min().x);
    EXPECT_EQ(box.hi.y, sources.max().y);
}

}  // namespace
}  // namespace beamtrace
