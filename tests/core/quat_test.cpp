#include "beamtrace/core/quat.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

namespace beamtrace {
namespace {

void expect_near(const Vec3d& a, const Vec3d& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Quat, FromRpyMatchesTheReportsRowVectorConvention) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> ang(-3.2, 3.2), comp(-1.0, 1.0);
    for (int i = 0; i < 200; ++i) {
        const RollPitchYaw rpy{ang(rng), ang(rng) / 2, ang(rng)};
        const Vec3d d{comp(rng), comp(rng), comp(rng)};
        expect_near(Quat::from_rpy(rpy).rotate(d), sensor_to_world(d, rpy_matrix(rpy)), 1e-12);
    }
    // Pitch -pi/2 looks straight down.
    expect_near(Quat::from_rpy({0, -std::numbers::pi / 2, 0}).rotate({1, 0, 0}), {0, 0, -1}, 1e-15);
}

TEST(Quat, ProductComposesAndMatrixRoundTrips) {
    const Quat a = Quat::from_axis_angle({0, 0, 1}, std::numbers::pi / 2);
    const Quat b = Quat::from_axis_angle({1, 0, 0}, std::numbers::pi / 2);
    const Vec3d v{0.3, -0.4, 1.2};
    expect_near((a * b).rotate(v), a.rotate(b.rotate(v)), 1e-15);
    expect_near(a.rotate({1, 0, 0}), {0, 1, 0}, 1e-15);  // right-handed about +z
    const Quat c = Quat::from_matrix((a * b).to_matrix());
    expect_near(c.rotate(v), (a * b).rotate(v), 1e-14);
    expect_near(a.conjugate().rotate(a.rotate(v)), v, 1e-15);
}

TEST(Quat, SlerpIsConstantSpeedAlongTheShorterArc) {
    const Quat a = Quat::identity();
    const Quat b = Quat::from_axis_angle({0, 0, 1}, 1.2);
    for (double t : {0.0, 0.25, 0.5, 1.0}) {
        expect_near(slerp(a, b, t).rotate({1, 0, 0}), {std::cos(1.2 * t), std::sin(1.2 * t), 0},
                    1e-12);
    }
    // -b is the same rotation: slerp must not take the long way round.
    const Quat nb{-b.w, -b.x, -b.y, -b.z};
    expect_near(slerp(a, nb, 0.5).rotate({1, 0, 0}), {std::cos(0.6), std::sin(0.6), 0}, 1e-12);
}

TEST(Pose, ComposesLikeNestedFrames) {
    const Pose platform{{100, 50, 10}, Quat::from_axis_angle({0, 0, 1}, std::numbers::pi / 2)};
    const Pose mount{{1, 0, -0.5}, Quat::identity()};  // lever arm 1 m forward, 0.5 m down
    const Pose sensor = platform * mount;
    expect_near(sensor.apply_point({0, 0, 0}), {100, 51, 9.5}, 1e-12);
    expect_near(sensor.apply_direction({1, 0, 0}), {0, 1, 0}, 1e-15);
}

}  // namespace
}  // namespace beamtrace
