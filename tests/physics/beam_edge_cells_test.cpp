// The probes of edge cells (beam_divergence.hpp): equal-energy sub-cells whose centroids average
// to their cell's, inside their cell; cell neighbours; which cells PulseSimulator refines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "beamtrace/physics/beam_divergence.hpp"
#include "beamtrace/physics/pulse.hpp"

namespace beamtrace {
namespace {

BeamConfig beam(int rings, int edge_samples) {
    BeamConfig c;
    c.divergence_rad = 1e-3;
    c.rings = rings;
    c.edge_samples = edge_samples;
    return c;
}

TEST(PhysicsBeamEdgeCells, ProbesShareTheirCellsEnergyAndAverageToItsCentroid) {
    for (const int rings : {1, 2, 3}) {
        for (const int n : {1, 2, 3, 5}) {
            const BeamConfig c = beam(rings, n);
            const auto cells = beam_pattern(c);
            const auto probes = cell_probe_pattern(c);
            const auto p = static_cast<std::size_t>(n * n);
            ASSERT_EQ(probes.size(), cells.size() * p);
            for (std::size_t j = 0; j < cells.size(); ++j) {
                double w = 0, x = 0, y = 0;
                for (std::size_t q = j * p; q < (j + 1) * p; ++q) {
                    EXPECT_NEAR(probes[q].weight, cells[j].weight / double(p), 1e-15);
                    EXPECT_NEAR(probes[q].off_axis_rad, probes[q].radius * 0.5e-3, 1e-18);
                    w += probes[q].weight;
                    x += probes[q].weight * probes[q].radius * std::cos(probes[q].azimuth_rad);
                    y += probes[q].weight * probes[q].radius * std::sin(probes[q].azimuth_rad);
                }
                // The sub-cells partition the cell with equal energies at their centroids: their
                // mean is the cell's centroid, where its sub-ray points.
                EXPECT_NEAR(w, cells[j].weight, 1e-15);
                EXPECT_NEAR(x / w, cells[j].radius * std::cos(cells[j].azimuth_rad), 1e-12)
                    << rings << " " << n << " " << j;
                EXPECT_NEAR(y / w, cells[j].radius * std::sin(cells[j].azimuth_rad), 1e-12);
            }
        }
    }
}

TEST(PhysicsBeamEdgeCells, ProbesLieInsideTheirCell) {
    const BeamConfig c = beam(2, 3);
    const auto probes = cell_probe_pattern(c);
    // Ring 1 (cells 1..6): radius in [0.25, 0.75], azimuth within 30 deg of the cell's centre.
    for (std::size_t j = 1; j <= 6; ++j) {
        const double centre = std::numbers::pi / 6 + double(j - 1) * std::numbers::pi / 3;
        for (std::size_t q = j * 9; q < (j + 1) * 9; ++q) {
            EXPECT_GT(probes[q].radius, 0.25);
            EXPECT_LT(probes[q].radius, 0.75);
            EXPECT_LT(std::abs(probes[q].azimuth_rad - centre), std::numbers::pi / 6);
        }
    }
    // Three radial bands of equal energy: the middle band's probes between the others'.
    EXPECT_LT(probes[9].radius, probes[12].radius);
    EXPECT_LT(probes[12].radius, probes[15].radius);
    EXPECT_TRUE(cell_probe_pattern(beam(2, 0)).empty());
    EXPECT_TRUE(cell_probe_pattern(beam(0, 3)).empty());
}

TEST(PhysicsBeamEdgeCells, NeighboursTouchEachOther) {
    const auto nb = cell_neighbours(beam(2, 3));
    ASSERT_EQ(nb.size(), 19u);
    EXPECT_EQ(nb[0], (std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6}));
    // Ring 1 cell 1 spans 0..60 deg: ring-1 cells 2 and 6, the centre, ring-2 cells at 0, 30,
    // 60 deg (7, 8, 9).
    EXPECT_EQ(nb[1], (std::vector<std::uint32_t>{0, 2, 6, 7, 8, 9}));
    // Ring 2 cell at 0 deg (7) touches ring-1 cells 1 (0..60) and 6 (300..360); at 30 deg (8)
    // only cell 1.
    EXPECT_EQ(nb[7], (std::vector<std::uint32_t>{1, 6, 8, 18}));
    EXPECT_EQ(nb[8], (std::vector<std::uint32_t>{1, 7, 9}));
    for (std::size_t a = 0; a < nb.size(); ++a) {
        for (const auto b : nb[a]) {
            EXPECT_NE(std::find(nb[b].begin(), nb[b].end(), a), nb[b].end()) << a << " " << b;
        }
    }
}

TEST(PhysicsBeamEdgeCells, EdgeCellsAreThoseWithANeighbourThatMetSomethingElse) {
    PhysicsConfig config;
    config.beam = beam(2, 3);
    const PulseSimulator sim(config);
    EXPECT_EQ(sim.probes_per_cell(), 9u);
    std::vector<std::int64_t> target(19, 4);
    std::vector<std::uint32_t> edges;
    sim.edge_cells(target, edges);
    EXPECT_TRUE(edges.empty());
    target[0] = -1;  // the centre sees through a hole: it and ring 1 are edges
    sim.edge_cells(target, edges);
    EXPECT_EQ(edges, (std::vector<std::uint32_t>{0, 1, 2, 3, 4, 5, 6}));
    target[0] = 4;
    target[8] = 7;  // a ring-2 cell on another part: it, its ring neighbours, ring-1 cell 1
    sim.edge_cells(target, edges);
    EXPECT_EQ(edges, (std::vector<std::uint32_t>{1, 7, 8, 9}));
    config.beam.edge_samples = 0;
    const PulseSimulator off(config);
    off.edge_cells(target, edges);
    EXPECT_TRUE(edges.empty());
}

TEST(PhysicsBeamEdgeCells, ProbeRaysPointAtTheirSubCells) {
    PhysicsConfig config;
    config.beam = beam(2, 2);
    const PulseSimulator sim(config);
    const auto probes = cell_probe_pattern(config.beam);
    const Vec3d axis = normalize(Vec3d{0.3, -0.2, -1.0});
    std::vector<Vec3d> origins(4), dirs(4);
    sim.probe_rays({1, 2, 3}, axis, 5, origins, dirs);
    for (std::size_t q = 0; q < 4; ++q) {
        EXPECT_EQ(origins[q].x, 1.0);
        EXPECT_NEAR(std::acos(std::clamp(dot(dirs[q], axis), -1.0, 1.0)),
                    probes[5 * 4 + q].off_axis_rad, 1e-9);
    }
}

}  // namespace
}  // namespace beamtrace
