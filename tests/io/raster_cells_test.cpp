// cells_floor (src/io/sinks/raster_cells.hpp): the preview's pixel of a coordinate by a
// multiplication gives exactly floor(d / cell), also at and next to cell edges.
#include "io/sinks/raster_cells.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace beamtrace::detail {
namespace {

void expect_as_division(double d, double cell) {
    const double expected = std::floor(d / cell);
    const double got = cells_floor(d, cell, 1.0 / cell);
    ASSERT_TRUE(got == expected || (std::isnan(got) && std::isnan(expected)))
        << "d " << d << " cell " << cell << ": " << got << " against " << expected;
}

TEST(RasterCells, CellsFloorIsTheFloorOfTheQuotient) {
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> offset(-3000.0, 3000.0);
    // Cells like the preview's (metres over 1024 pixels) and awkward ones (1/3, 0.1).
    for (const double cell : {1.87, 5.859375, 0.1, 1.0 / 3.0, 7.000000000000001, 123.456}) {
        for (int i = 0; i < 20000; ++i) {
            expect_as_division(offset(rng), cell);
        }
        // On cell edges and one or two ulps either side, where the product may round across.
        for (int k = -2000; k <= 2000; ++k) {
            const double edge = k * cell;
            double d = edge;
            for (int step = 0; step < 3; ++step) {
                expect_as_division(d, cell);
                d = std::nextafter(d, -std::numeric_limits<double>::infinity());
            }
            d = edge;
            for (int step = 0; step < 3; ++step) {
                d = std::nextafter(d, std::numeric_limits<double>::infinity());
                expect_as_division(d, cell);
            }
        }
    }
    for (const double d :
         {0.0, -0.0, 1e-300, -1e-300, 1e300, std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::quiet_NaN()}) {
        expect_as_division(d, 1.87);
    }
}

/// cells_floor_pair() gives cells_floor()'s doubles bit for bit, lane by lane, whether both
/// lanes are clear of an edge (the SSE2 lanes), one is not, or one is zero, huge or NaN.
TEST(RasterCells, CellsFloorPairIsCellsFloorOfEach) {
    std::mt19937_64 rng(22);
    std::uniform_real_distribution<double> offset(-3000.0, 3000.0);
    std::vector<double> ds;
    for (int i = 0; i < 20000; ++i) {
        ds.push_back(offset(rng));
    }
    for (const double cell : {1.87, 0.1, 1.0 / 3.0}) {
        for (int k = -300; k <= 300; ++k) {
            ds.push_back(k * cell);
            ds.push_back(std::nextafter(k * cell, 1e300));
            ds.push_back(std::nextafter(k * cell, -1e300));
        }
    }
    for (const double d :
         {0.0, -0.0, 1e-300, -1e-300, 0.5, -0.5, 1e300, -1e300, 4.1e9, -4.1e9,
          std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
        ds.push_back(d);
    }
    std::vector<double> others = ds;
    std::shuffle(others.begin(), others.end(), rng);
    for (const double cell : {1.87, 0.1, 1.0 / 3.0, 0.3}) {
        for (std::size_t i = 0; i < ds.size(); ++i) {
            double got[2];
            cells_floor_pair(ds[i], others[i], cell, 1.0 / cell, got);
            const double expected[2] = {cells_floor(ds[i], cell, 1.0 / cell),
                                        cells_floor(others[i], cell, 1.0 / cell)};
            ASSERT_EQ(std::memcmp(got, expected, sizeof got), 0)
                << "d " << ds[i] << ", " << others[i] << " cell " << cell << ": " << got[0] << ", "
                << got[1] << " against " << expected[0] << ", " << expected[1];
        }
    }
}

}  // namespace
}  // namespace beamtrace::detail
