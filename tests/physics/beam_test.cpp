#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "beamtrace/physics/beam_divergence.hpp"

namespace beamtrace {
namespace {

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
    EXPECT_NEAR(p[1].off_axis_rad, 0.25e-3, 1e-15);
    EXPECT_NEAR(p[18].off_axis_rad, 0.5e-3, 1e-15);  // the outer ring on the half-angle
    EXPECT_GT(p[0].weight, p[1].weight);
    EXPECT_GT(p[1].weight, p[7].weight);
    // rings = 1: centre disc of radius w/2, ring annulus [w/2, 3w/2] of the profile
    // exp(-2 t^2 / w^2): shares 1 - e^-0.5 and e^-0.5 - e^-4.5, normalised.
    c.rings = 1;
    const auto q = beam_pattern(c);
    ASSERT_EQ(q.size(), 7u);
    const double centre = 1 - std::exp(-0.5), ring = std::exp(-0.5) - std::exp(-4.5);
    EXPECT_NEAR(q[0].weight, centre / (centre + ring), 1e-12);
    EXPECT_NEAR(q[3].weight, ring / 6 / (centre + ring), 1e-12);
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

TEST(PhysicsBeam, Validate) {
    BeamConfig c;
    EXPECT_TRUE(c.validate().empty());
    c.divergence_rad = -1;
    c.rings = 50;
    EXPECT_EQ(c.validate().size(), 2u);
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
