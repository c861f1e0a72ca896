// preview_cells (src/io/sinks/preview_cells.hpp): the preview's pixel and height of each point,
// in AVX2 lanes, the same as one point at a time (and as the division) on and beside cell edges;
// row_hits, the box and height range of a raster row's hits.
#include "io/sinks/preview_cells.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace beamtrace::detail {
namespace {

struct Cells {
    std::vector<std::uint32_t> pixel;
    std::vector<float> height;
};

Cells cells_of(const std::vector<BlockPoint>& points, const PreviewGrid& grid, bool lanes) {
    Cells c{std::vector<std::uint32_t>(points.size()), std::vector<float>(points.size())};
    const std::size_t n = lanes
                              ? preview_cells(points, grid, c.pixel.data(), c.height.data())
                              : preview_cells_scalar(points, grid, c.pixel.data(), c.height.data());
    c.pixel.resize(n);
    c.height.resize(n);
    return c;
}

BlockPoint point_at(double x, double y, double z) {
    BlockPoint p;
    p.x = x;
    p.y = y;
    p.z = z;
    p.gps_time = 1e9;  // loaded with x, y, z by the lanes, never used
    return p;
}

/// The lanes' pixels and heights are the scalar code's, bit for bit (heights compared as bits:
/// -0 must come out +0 both ways).
void expect_lanes_as_scalar(const std::vector<BlockPoint>& points, const PreviewGrid& grid) {
    const Cells lanes = cells_of(points, grid, true), scalar = cells_of(points, grid, false);
    ASSERT_EQ(lanes.pixel, scalar.pixel);
    ASSERT_EQ(lanes.height.size(), scalar.height.size());
    for (std::size_t i = 0; i < lanes.height.size(); ++i) {
        std::uint32_t a = 0, b = 0;
        std::memcpy(&a, &lanes.height[i], sizeof a);
        std::memcpy(&b, &scalar.height[i], sizeof b);
        ASSERT_EQ(a, b) << "point " << i;
    }
}

TEST(PreviewCells, PixelsRowsFromTheNorthColumnsFromTheWest) {
    const PreviewGrid grid{100.0, 50.0, 2.0, 0.5, 10, 5};  // x 100..120, y 40..50
    const std::vector<BlockPoint> points{
        point_at(101.0, 49.0, 3.0),   // column 0, row 0
        point_at(119.9, 40.1, -0.0),  // column 9, row 4: -0 as +0
        point_at(99.9, 45.0, 1.0),    // west of the grid
        point_at(105.0, 50.5, 1.0),   // north of it
        point_at(120.0, 45.0, 1.0),   // on its east edge: off
        point_at(104.0, 44.0, 7.5),   // on the edge of columns 1 and 2, rows 2 and 3
        point_at(std::nan(""), 45.0, 1.0),
    };
    for (const bool lanes : {true, false}) {
        const Cells c = cells_of(points, grid, lanes);
        EXPECT_EQ(c.pixel, (std::vector<std::uint32_t>{0, 49, 32})) << lanes;
        ASSERT_EQ(c.height.size(), 3u);
        EXPECT_EQ(c.height[0], 3.0f);
        EXPECT_FALSE(std::signbit(c.height[1])) << lanes;
        EXPECT_EQ(c.height[2], 7.5f);
    }
}

TEST(PreviewCells, LanesAsOnePointAtATimeOnAndBesideCellEdges) {
    std::mt19937_64 rng(2121);
    for (const double cell : {5.859375, 1.87, 0.1, 1.0 / 3.0, 7.000000000000001}) {
        const PreviewGrid grid{-3000.0, 1000.0, cell, 1.0 / cell, 1024, 700};
        std::vector<BlockPoint> points;
        std::uniform_real_distribution<double> x(-3100.0, -3000.0 + 1030 * cell);
        std::uniform_real_distribution<double> y(1000.0 - 710 * cell, 1100.0);
        for (int i = 0; i < 20000; ++i) {
            points.push_back(point_at(x(rng), y(rng), x(rng) / 7.0));
        }
        // Coordinates on cell edges and an ulp or two either side of them, in both axes.
        for (int k = -3; k < 1030; ++k) {
            double dx = -3000.0 + k * cell, dy = 1000.0 - k * cell;
            for (int step = 0; step < 5; ++step) {
                points.push_back(point_at(dx, dy, k));
                points.push_back(point_at(dx, 999.5 - cell * (k % 700), -0.0));
                dx = std::nextafter(dx, -std::numeric_limits<double>::infinity());
                dy = std::nextafter(dy, std::numeric_limits<double>::infinity());
            }
        }
        points.push_back(point_at(std::numeric_limits<double>::infinity(), 0.0, 1.0));
        points.push_back(point_at(-2999.0, std::nan(""), 1.0));
        points.push_back(point_at(-2999.0, 999.0, 1.0));  // a tail of one past the lanes
        expect_lanes_as_scalar(points, grid);
    }
}

TEST(PreviewCells, RowHitsFirstLastLowestHighest) {
    const float empty = -std::numeric_limits<float>::infinity();
    // Rows of every width 0..40 with hits placed around the lanes' edges, and random ones.
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> z(-50.0f, 900.0f);
    for (int width = 0; width <= 40; ++width) {
        for (int round = 0; round < 60; ++round) {
            std::vector<float> row(static_cast<std::size_t>(width), empty);
            for (int k = 0; k < round % 5 && width > 0; ++k) {
                row[rng() % static_cast<unsigned>(width)] = z(rng);
            }
            const RowHits lanes = row_hits(row.data(), width, empty);
            const RowHits scalar = row_hits_scalar(row.data(), width, empty);
            ASSERT_EQ(lanes.first, scalar.first) << width << " " << round;
            ASSERT_EQ(lanes.last, scalar.last) << width << " " << round;
            if (scalar.first >= 0) {
                ASSERT_EQ(lanes.lo, scalar.lo) << width << " " << round;
                ASSERT_EQ(lanes.hi, scalar.hi) << width << " " << round;
            }
        }
    }
    std::vector<float> row(37, empty);
    row[3] = 5.0f;
    row[9] = -2.0f;
    row[20] = 0.0f;
    row[33] = 7.5f;
    for (const bool lanes : {true, false}) {
        const RowHits h =
            lanes ? row_hits(row.data(), 37, empty) : row_hits_scalar(row.data(), 37, empty);
        EXPECT_EQ(h.first, 3);
        EXPECT_EQ(h.last, 33);
        EXPECT_EQ(h.lo, -2.0f);
        EXPECT_EQ(h.hi, 7.5f);
    }
    EXPECT_EQ(row_hits(row.data(), 3, empty).first, -1);
}

}  // namespace
}  // namespace beamtrace::detail
