// The one albedo pattern of `render` and surveys, on each surface it is laid on.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "beamtrace/physics/material.hpp"

namespace beamtrace {
namespace {

Material patterned(AlbedoPatternKind kind, int count, double size_m) {
    Material m;
    m.reflectance = 0.9;
    m.pattern = {kind, count, size_m, 0.2, {}};
    return m;
}

TEST(AlbedoPattern, SphereStripesAreLongitudeSegments) {
    const Material m = patterned(AlbedoPatternKind::stripes, 4, 1.0);
    const PatternFrame f = PatternFrame::sphere({0, 0, 0}, 1.0, Quat{});
    // Segments start at longitude -180 degrees: [-180, -90) base, [-90, 0) alternate, ...
    EXPECT_EQ(albedo(m, f, {-1, -0.1, 0}), 0.9);
    EXPECT_EQ(albedo(m, f, {0.1, -1, 0}), 0.2);
    EXPECT_EQ(albedo(m, f, {1, 0.1, 0}), 0.9);
    EXPECT_EQ(albedo(m, f, {-1, 0.1, 0}), 0.2);
    // The centre, radius and attitude place them: turned 90 degrees about z (either way), the
    // point at world longitude -45 degrees (an alternate segment unturned) lies in a base one.
    const Quat yaw = Quat::from_rpy({0, 0, std::numbers::pi / 2});
    const PatternFrame turned = PatternFrame::sphere({5, 0, 0}, 2.0, yaw);
    const Vec3d at{5 + std::sqrt(2.0), -std::sqrt(2.0), 0};
    EXPECT_EQ(albedo(m, PatternFrame::sphere({5, 0, 0}, 2.0, Quat{}), at), 0.2);
    EXPECT_EQ(albedo(m, turned, at), 0.9);
}

TEST(AlbedoPattern, SphereCheckerAddsLatitudeBands) {
    const Material m = patterned(AlbedoPatternKind::checker, 4, 1.0);
    const PatternFrame f = PatternFrame::sphere({0, 0, 0}, 1.0, Quat{});
    // Two latitude bands: the southern one flips every segment.
    EXPECT_EQ(albedo(m, f, normalize(Vec3d{-1, -0.1, 0.5})), 0.2);
    EXPECT_EQ(albedo(m, f, normalize(Vec3d{-1, -0.1, -0.5})), 0.9);
    EXPECT_EQ(albedo(m, f, normalize(Vec3d{0.1, -1, -0.5})), 0.2);
}

TEST(AlbedoPattern, PlaneUsesMetresAlongItsAxes) {
    const Material m = patterned(AlbedoPatternKind::checker, 2, 1.0);
    const PatternFrame f = PatternFrame::plane({10, 0, 0}, {0, 1, 0}, {0, 0, 1});
    EXPECT_EQ(albedo(m, f, {10, 0.5, 1.5}), 0.2);
    EXPECT_EQ(albedo(m, f, {10, 1.5, 1.5}), 0.9);
    EXPECT_EQ(albedo(m, f, {10, -0.5, 0.5}), 0.2);
    const Material s = patterned(AlbedoPatternKind::stripes, 2, 0.5);
    EXPECT_EQ(albedo(s, f, {10, 0.25, 7}), 0.9);
    EXPECT_EQ(albedo(s, f, {10, 0.75, -3}), 0.2);
}

TEST(AlbedoPattern, SolidStripesAlongXAndThreeDChecker) {
    Material m = patterned(AlbedoPatternKind::stripes, 2, 1.0);
    EXPECT_EQ(albedo(m, {0.5, 7, 3}), 0.9);
    EXPECT_EQ(albedo(m, {1.5, -7, 3}), 0.2);
    EXPECT_EQ(albedo(m, {-0.5, 0, 0}), 0.2);
    EXPECT_EQ(albedo(m, PatternFrame{}, {2.5, 0, 0}), 0.9);
    m.pattern.kind = AlbedoPatternKind::checker;
    EXPECT_EQ(albedo(m, {0.5, 0.5, 0.5}), 0.9);
    EXPECT_EQ(albedo(m, {1.5, 0.5, 0.5}), 0.2);
    EXPECT_EQ(albedo(m, {1.5, 1.5, 0.5}), 0.9);
    EXPECT_EQ(albedo(m, {1.5, 1.5, 1.5}), 0.2);
    m.pattern.kind = AlbedoPatternKind::uniform;
    EXPECT_EQ(albedo(m, {1.5, 0.5, 0.5}), 0.9);
    EXPECT_EQ(albedo(m, PatternFrame::sphere({0, 0, 0}, 1, Quat{}), {0.1, -1, 0}), 0.9);
}

}  // namespace
}  // namespace beamtrace
