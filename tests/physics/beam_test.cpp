#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <vector>

#include "beamtrace/physics/beam_divergence.hpp"

namespace beamtrace {
namespace {

/// The centroid radius (beam units) of one of `count` equal sectors of the annulus [lo, hi]
/// under the profile exp(-2 u^2), by numerical integration.
double sector_centroid(double lo, double hi, int count) {
    const int n = 20000;
    double m0 = 0, m1 = 0;
    for (int i = 0; i < n; ++i) {
        const double u = lo + (hi - lo) * (i + 0.5) / n;
        m0 += u * std::exp(-2 * u * u);
        m1 += u * u * std::exp(-2 * u * u);
    }
    const double half = std::numbers::pi / count;
    return m1 / m0 * std::sin(half) / half;
}

TEST(PhysicsBeam, NineteenSubRaysWithGaussianWeights) {
    BeamConfig c;
    c.divergence_rad = 1e-3;
    c.rings = 2;
    const auto p = beam_pattern(c);
    ASSERT_EQ(p.size(), 19u);
    EXPECT_EQ(sub_ray_count(c), 19u);
    double total = 0;
    for (const auto& s : p) {
        EXPECT_GT(s.weight, 0);
        total += s.weight;
    }
    EXPECT_NEAR(total, 1.0, 1e-12);
    EXPECT_EQ(p[0].off_axis_rad, 0.0);
    // Ring 1 at the centroid of its 60 deg sectors of the annulus [w/4, 3w/4], ring 2 of its
    // 30 deg sectors of [3w/4, inf) (the tail belongs to the outermost ring).
    EXPECT_NEAR(p[1].off_axis_rad, 0.5e-3 * sector_centroid(0.25, 0.75, 6), 1e-9);
    EXPECT_NEAR(p[18].off_axis_rad, 0.5e-3 * sector_centroid(0.75, 6.0, 12), 1e-9);
    EXPECT_NEAR(p[18].radius, p[18].off_axis_rad / 0.5e-3, 1e-12);
    EXPECT_GT(p[0].weight, p[1].weight);
    EXPECT_GT(p[1].weight, p[7].weight);
    // rings = 1: centre disc of radius w/2, ring annulus [w/2, inf) of the profile
    // exp(-2 t^2 / w^2): shares 1 - e^-0.5 and e^-0.5, summing to 1.
    c.rings = 1;
    const auto q = beam_pattern(c);
    ASSERT_EQ(q.size(), 7u);
    EXPECT_NEAR(q[0].weight, 1 - std::exp(-0.5), 1e-12);
    EXPECT_NEAR(q[3].weight, std::exp(-0.5) / 6, 1e-12);
    // No divergence: one ray.
    c.divergence_rad = 0;
    EXPECT_EQ(beam_pattern(c).size(), 1u);
    EXPECT_EQ(beam_pattern(c)[0].weight, 1.0);
    c.rings = 3;
    c.divergence_rad = 1e-3;
    EXPECT_EQ(beam_pattern(c).size(), 37u);
}

TEST(PhysicsBeam, DirectionsLieOnTheConeAroundAnyAxis) {
    BeamConfig c;
    c.divergence_rad = 2e-3;
    const auto p = beam_pattern(c);
    for (const Vec3d raw : {Vec3d{1, 0, 0}, Vec3d{0, 0, 1}, Vec3d{0, 0, -1}, Vec3d{0.3, -2, 0.5},
                            Vec3d{1e-9, 0, -1}}) {
        const Vec3d axis = normalize(raw);
        Vec3d e1, e2;
        orthonormal_basis(axis, e1, e2);
        EXPECT_NEAR(dot(e1, axis), 0, 1e-12);
        EXPECT_NEAR(dot(e2, axis), 0, 1e-12);
        EXPECT_NEAR(dot(e1, e2), 0, 1e-12);
        EXPECT_NEAR(length(e1), 1, 1e-12);
        EXPECT_NEAR(dot(cross(e1, e2), axis), 1, 1e-12);  // right-handed
        std::vector<Vec3d> dirs(p.size());
        sub_ray_directions(axis, p, dirs);
        Vec3d centroid{0, 0, 0};
        for (std::size_t i = 0; i < p.size(); ++i) {
            EXPECT_NEAR(length(dirs[i]), 1.0, 1e-12);
            const double ang = std::acos(std::min(1.0, dot(dirs[i], axis)));
            EXPECT_NEAR(ang, p[i].off_axis_rad, 1e-7);
            centroid += dirs[i] * p[i].weight;
        }
        // The weighted pattern is symmetric about the axis.
        EXPECT_NEAR(length(cross(centroid, axis)), 0.0, 1e-12);
        // Deterministic.
        std::vector<Vec3d> again(p.size());
        sub_ray_directions(axis, p, again);
        EXPECT_EQ(dirs, again);
    }
}

// The beam-frame directions (AVX2: one direction to a register, each store but the last four
// doubles wide) are e1 b.x + e2 b.y + axis b.z, bit for bit, and write nothing past the end.
TEST(PhysicsBeam, BeamFrameDirectionsAreTheBasisSumsBitForBit) {
    std::uint64_t s = 3;
    const auto next = [&s] {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(s >> 11) * 0x1p-53 - 0.5;
    };
    for (int trial = 0; trial < 500; ++trial) {
        const Vec3d axis = normalize(Vec3d{next(), next(), next()});
        std::vector<Vec3d> frame(1 + static_cast<std::size_t>(trial) % 40);
        for (Vec3d& b : frame) {
            b = {1e-3 * next(), 1e-3 * next(), 1.0 + 1e-6 * next()};
        }
        std::vector<Vec3d> got(frame.size() + 1, Vec3d{-0.0, -0.0, -0.0});
        sub_ray_directions(axis, frame, std::span<Vec3d>(got.data(), frame.size()));
        Vec3d e1, e2;
        orthonormal_basis(axis, e1, e2);
        for (std::size_t i = 0; i < frame.size(); ++i) {
            const Vec3d want = e1 * frame[i].x + e2 * frame[i].y + axis * frame[i].z;
            for (int c = 0; c < 3; ++c) {
                ASSERT_EQ(std::bit_cast<std::uint64_t>((&got[i].x)[c]),
                          std::bit_cast<std::uint64_t>((&want.x)[c]))
                    << "trial " << trial << " direction " << i << " component " << c;
            }
        }
        EXPECT_EQ(std::bit_cast<std::uint64_t>(got.back().x), std::bit_cast<std::uint64_t>(-0.0));
    }
}

TEST(PhysicsBeam, Validate) {
    BeamConfig c;
    EXPECT_TRUE(c.validate().empty());
    c.divergence_rad = -1;
    c.rings = 50;
    EXPECT_EQ(c.validate().size(), 2u);
    c = BeamConfig{};
    c.exit_diameter_m = -0.01;
    EXPECT_EQ(c.validate().size(), 1u);
}

// The cells partition the plane: the pattern's variance plus the mean within-cell variance is
// the beam's 1/4 per axis (law of total variance), checked by integrating over the cells.
TEST(PhysicsBeam, CellVarianceIsTheMeanWithinCellVariance) {
    for (const int rings : {0, 1, 2, 3}) {
        BeamConfig c;
        c.divergence_rad = 1e-3;
        c.rings = rings;
        const auto p = beam_pattern(c);
        const double d = rings > 0 ? 1.0 / rings : 0.0;
        // Grid over [-3, 3]^2 in beam units: each point's cell, its squared x-distance from the
        // cell's sub-ray, weighted by the profile.
        const int n = 900;
        double mass = 0, within = 0;
        for (int a = 0; a < n; ++a) {
            for (int b = 0; b < n; ++b) {
                const double x = -3 + 6.0 * (a + 0.5) / n, y = -3 + 6.0 * (b + 0.5) / n;
                const double u = std::hypot(x, y), g = std::exp(-2 * u * u);
                std::size_t j = 0;
                if (rings > 0) {
                    const int k = std::min(rings, static_cast<int>(std::floor(u / d + 0.5)));
                    if (k > 0) {
                        const int count = 6 * k;
                        const double step = 2 * std::numbers::pi / count;
                        const double phase = k % 2 == 1 ? step / 2 : 0.0;
                        double az = std::atan2(y, x) - phase + step / 2;
                        az -= 2 * std::numbers::pi * std::floor(az / (2 * std::numbers::pi));
                        j = 1 + 3 * static_cast<std::size_t>(k) * (k - 1) +
                            std::min<std::size_t>(count - 1, static_cast<std::size_t>(az / step));
                    }
                }
                const double cx = p[j].radius * std::cos(p[j].azimuth_rad);
                mass += g;
                within += g * (x - cx) * (x - cx);
            }
        }
        EXPECT_NEAR(cell_variance(p), within / mass, 2e-4) << rings;
        double discrete = 0;
        for (const auto& s : p) {
            discrete += 0.5 * s.weight * s.radius * s.radius;
        }
        EXPECT_NEAR(discrete + cell_variance(p), 0.25, 1e-12) << rings;
        EXPECT_GT(cell_variance(p), 0.0) << rings;
    }
}

// Exit pupil: sub-ray j starts at (D0/2) u_j perpendicular to its angular offset, so at any
// range z it lies at radius u_j W(z) from the axis, W(z) = sqrt((D0/2)^2 + (z theta/2)^2).
TEST(PhysicsBeam, ExitDiameterPutsSubRaysOnTheGaussianBeamEnvelope) {
    for (const double div : {0.5e-3, 0.0}) {
        BeamConfig c;
        c.divergence_rad = div;
        c.exit_diameter_m = 0.04;
        c.rings = 2;
        const auto p = beam_pattern(c);
        ASSERT_EQ(p.size(), 19u);
        const auto offsets = beam_frame_origins(c, p);
        const auto frame = beam_frame_directions(p);
        const Vec3d axis = normalize(Vec3d{0.3, -0.5, -1});
        const Vec3d origin{10, 20, 30};
        std::vector<Vec3d> origins(p.size()), dirs(p.size());
        sub_ray_origins(origin, axis, offsets, origins);
        sub_ray_directions(axis, frame, dirs);
        for (const double z : {0.0, 10.0, 100.0, 2000.0}) {
            const double w = footprint_radius_m(c, z);
            EXPECT_NEAR(w, std::hypot(0.02, z * div / 2), 1e-15);
            for (std::size_t j = 0; j < p.size(); ++j) {
                // Where ray j crosses the plane at axial distance z.
                const double t = (z - dot(origins[j] - origin, axis)) / dot(dirs[j], axis);
                const Vec3d at = origins[j] + dirs[j] * t - origin;
                const double radial = length(at - axis * dot(at, axis));
                EXPECT_NEAR(radial, p[j].radius * w, 1e-9 + 1e-6 * w)
                    << div << " " << z << " " << j;
            }
        }
    }
    // D0 = 0: no offsets.
    BeamConfig c;
    c.divergence_rad = 0.5e-3;
    for (const Vec3d& o : beam_frame_origins(c, beam_pattern(c))) {
        EXPECT_EQ(o, (Vec3d{0, 0, 0}));
    }
    // An exit diameter without divergence still samples the (collimated) beam.
    c.divergence_rad = 0;
    c.exit_diameter_m = 0.01;
    EXPECT_EQ(sub_ray_count(c), 19u);
}

}  // namespace
}  // namespace beamtrace

namespace beamtrace {
namespace {

TEST(PhysicsBeam, PrecomputedFrameGivesTheSameDirections) {
    BeamConfig c;
    c.divergence_rad = 4e-3;
    c.rings = 3;
    const auto p = beam_pattern(c);
    const auto frame = beam_frame_directions(p);
    const Vec3d axis = normalize(Vec3d{-0.2, 0.7, -1});
    std::vector<Vec3d> a(p.size()), b(p.size());
    sub_ray_directions(axis, p, a);
    sub_ray_directions(axis, frame, b);
    for (std::size_t i = 0; i < p.size(); ++i) {
        EXPECT_NEAR(length(a[i] - b[i]), 0.0, 1e-15) << i;
        EXPECT_NEAR(length(b[i]), 1.0, 1e-15);
    }
}

}  // namespace
}  // namespace beamtrace
