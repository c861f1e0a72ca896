// Moving parts (docs/scene-file.md, `motion:`): the motions' closed forms, their velocities
// against finite differences, the swept bounds against sampled placements, parsing errors with
// file:line: key, and how build_scene numbers moving parts, objects and faces.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/geometry/rigid_motion.hpp"
#include "beamtrace/scene/scene_builder.hpp"
#include "beamtrace/scene/scene_spec.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

void expect_near(const Vec3d& a, const Vec3d& b, double tol, const std::string& what = "") {
    EXPECT_NEAR(a.x, b.x, tol) << what;
    EXPECT_NEAR(a.y, b.y, tol) << what;
    EXPECT_NEAR(a.z, b.z, tol) << what;
}

RigidMotion two_keys() {
    RigidMotion m;
    m.keys.push_back({1.0, {0, 0, 0}, Quat{}});
    m.keys.push_back({3.0, {10, -4, 2}, Quat::from_axis_angle({0, 0, 1}, kPi / 2)});
    return m;
}

TEST(RigidMotion, KeyframesInterpolateLinearlyAndBySlerpAndHoldOutside) {
    const RigidMotion m = two_keys();
    const Pose mid = m.at(2.0);
    expect_near(mid.position_m, {5, -2, 1}, 1e-12);
    // Halfway: a turn of 45 degrees about z takes +x to (cos 45, sin 45, 0).
    expect_near(mid.attitude.rotate({1, 0, 0}), {std::sqrt(0.5), std::sqrt(0.5), 0}, 1e-12);
    const Pose quarter = m.at(1.5);
    expect_near(quarter.position_m, {2.5, -1, 0.5}, 1e-12);
    expect_near(quarter.attitude.rotate({1, 0, 0}), {std::cos(kPi / 8), std::sin(kPi / 8), 0},
                1e-12);
    // Held before the first key and after the last.
    expect_near(m.at(-5.0).position_m, {0, 0, 0}, 0.0);
    expect_near(m.at(99.0).position_m, {10, -4, 2}, 0.0);
    expect_near(m.at(99.0).attitude.rotate({1, 0, 0}), {0, 1, 0}, 1e-15);
    expect_near(m.point_velocity({3, 3, 3}, 0.5), {0, 0, 0}, 0.0);
    expect_near(m.point_velocity({3, 3, 3}, 4.0), {0, 0, 0}, 0.0);
}

TEST(RigidMotion, ConstantVelocityAndSpinAboutThePivot) {
    RigidMotion m;
    m.pivot_m = {1, 2, 3};
    m.velocity_mps = {4, 0, -1};
    m.spin_axis = {0, 0, 1};
    m.spin_rate_rad_s = kPi;  // half a turn per second
    const Pose p = m.at(0.5);
    expect_near(p.position_m, {3, 2, 2.5}, 1e-15);
    expect_near(p.attitude.rotate({1, 0, 0}), {0, 1, 0}, 1e-15);
    // A point 1 m in +x of the pivot moves with v plus omega x r.
    expect_near(m.point_velocity(p.position_m + Vec3d{0, 1, 0}, 0.5), {4 - kPi, 0, -1}, 1e-12);
}

/// Velocity of the body point that is at `local` in the motion's frame: a central difference of
/// its position, against point_velocity.
void expect_velocity_is_derivative(const RigidMotion& m, double t, const Vec3d& local) {
    const double h = 1e-6;
    const Vec3d before = m.at(t - h).apply_point(local);
    const Vec3d after = m.at(t + h).apply_point(local);
    const Vec3d numeric = (after - before) * (0.5 / h);
    expect_near(m.point_velocity(m.at(t).apply_point(local), t), numeric, 1e-6,
                "t = " + std::to_string(t));
}

TEST(RigidMotion, PointVelocityIsTheDerivativeOfThePointsPosition) {
    RigidMotion keys = two_keys();
    keys.keys.push_back({4.0, {12, -4, 2}, Quat::from_rpy({0.3, -0.2, 2.0})});
    for (const double t : {1.3, 2.0, 2.9, 3.4}) {
        expect_velocity_is_derivative(keys, t, {2, -1, 0.5});
    }
    RigidMotion spin;
    spin.pivot_m = {5, 0, 0};
    spin.velocity_mps = {0, 3, 0};
    spin.spin_axis = normalize(Vec3d{1, 1, 0});
    spin.spin_rate_rad_s = 2.5;
    for (const double t : {0.0, 0.7, 11.0}) {
        expect_velocity_is_derivative(spin, t, {0, 0, 4});
    }
}

TEST(RigidMotion, SweptBoundsHoldTheMeshAtEveryTime) {
    const Aabb object{{-1, -2, 0}, {1, 2, 0.5}};
    MovingInstance mi;
    mi.local.translation = {0.5, 0, 0};
    mi.offset_m = {0, 100, 0};
    RigidMotion spin;
    spin.pivot_m = {3, 0, 0};
    spin.velocity_mps = {20, 0, 0};
    spin.spin_axis = {0, 1, 0};
    spin.spin_rate_rad_s = 4.0;
    RigidMotion slide;
    slide.velocity_mps = {-30, 5, 0};
    for (const RigidMotion& motion : {spin, slide, two_keys()}) {
        const double t0 = 0.9, t1 = 2.2;
        const Aabb box = mi.swept_bounds(object, motion, t0, t1);
        for (int s = 0; s <= 200; ++s) {
            const double t = t0 + (t1 - t0) * s / 200.0;
            const Affine3 w = mi.to_world(motion.at(t));
            for (int c = 0; c < 8; ++c) {
                const Vec3d corner((c & 1) ? object.hi.x : object.lo.x,
                                   (c & 2) ? object.hi.y : object.lo.y,
                                   (c & 4) ? object.hi.z : object.lo.z);
                const Vec3d p = w.apply_point(corner);
                for (std::size_t a = 0; a < 3; ++a) {
                    ASSERT_LE(box.lo[a], p[a]) << "t " << t << " axis " << a;
                    ASSERT_GE(box.hi[a], p[a]) << "t " << t << " axis " << a;
                }
            }
        }
    }
    // Without rotation the box is tight: the slide's path plus the mesh's box.
    const Aabb tight = mi.swept_bounds(object, slide, 0.0, 1.0);
    EXPECT_NEAR(tight.lo.x, -30 - 0.5, 1e-3);
    EXPECT_NEAR(tight.hi.x, 1.5, 1e-3);
}

/// The message of the ConfigError that parsing `yaml` (as dir/scene.yaml) throws.
std::string error_of(const std::string& yaml) {
    test::TempDir dir;
    test::write_file(dir / "box.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    try {
        (void)parse_scene_spec(yaml, dir / "scene.yaml");
    } catch (const ConfigError& e) {
        const std::string m = e.what();
        const auto at = m.find("scene.yaml:");
        return at == std::string::npos ? m : m.substr(at);
    }
    return "no error";
}

TEST(SceneMotion, ParsesKeyframesAndConstantMotions) {
    test::TempDir dir;
    test::write_file(dir / "box.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const SceneSpec s = parse_scene_spec(R"(parts:
  - mesh: box.obj
    motion:
      keyframes:
        - {time_s: 0, position_m: [1, 2, 3]}
        - {time_s: 2.5, position_m: [4, 5, 6], rotate_deg: [0, 0, 90]}
  - mesh: box.obj
    transform: {translate_m: [7, 0, 0]}
    motion: {velocity_mps: [1, 0, 0], spin: {axis: [0, 0, 2], rate_rad_s: 0.5}}
  - mesh: box.obj
)",
                                         dir / "scene.yaml");
    ASSERT_EQ(s.parts.size(), 3u);
    ASSERT_TRUE(s.parts[0].motion);
    ASSERT_EQ(s.parts[0].motion->keys.size(), 2u);
    EXPECT_EQ(s.parts[0].motion->keys[1].time_s, 2.5);
    expect_near(s.parts[0].motion->keys[1].attitude.rotate({1, 0, 0}), {0, -1, 0}, 1e-12,
                "yaw 90 in the report's convention");
    ASSERT_TRUE(s.parts[1].motion);
    expect_near(s.parts[1].motion->spin_axis, {0, 0, 1}, 0.0, "unit axis");
    EXPECT_EQ(s.parts[1].motion->spin_rate_rad_s, 0.5);
    EXPECT_FALSE(s.parts[1].motion->pivot_m);
    EXPECT_FALSE(s.parts[2].motion);
}

TEST(SceneMotion, RefusesBadMotionsWithFileLineAndKey) {
    EXPECT_EQ(error_of("parts:\n  - mesh: box.obj\n    motion:\n      keyframes:\n"
                       "        - {time_s: 2}\n        - {time_s: 1}\n"),
              "scene.yaml:6: parts[0].motion.keyframes[1].time_s: keys must be in strictly "
              "increasing time (1.000000 s after 2.000000 s)");
    EXPECT_EQ(error_of("parts:\n  - mesh: box.obj\n    motion:\n      keyframes: [{time_s: 0}]\n"
                       "      velocity_mps: [1, 0, 0]\n"),
              "scene.yaml:5: parts[0].motion.velocity_mps: not with keyframes (a part moves by "
              "keyframes or by a constant velocity and spin)");
    EXPECT_EQ(error_of("parts:\n  - mesh: box.obj\n    motion: {spin: {axis: [0, 0, 0], "
                       "rate_rad_s: 1}}\n"),
              "scene.yaml:3: parts[0].motion.spin.axis: must not be zero");
    EXPECT_EQ(error_of("parts:\n  - mesh: box.obj\n    motion: {spin: {axis: [0, 0, 1]}}\n"),
              "scene.yaml:3: parts[0].motion.spin.rate_rad_s: missing");
    EXPECT_EQ(error_of("parts:\n  - mesh: box.obj\n    motion: {}\n"),
              "scene.yaml:3: parts[0].motion: expected keyframes, or velocity_mps and/or spin");
    EXPECT_EQ(error_of("parts:\n  - mesh: box.obj\n    motion: {velocity_mps: [1, 0]}\n"),
              "scene.yaml:3: parts[0].motion.velocity_mps: expected three numbers [x, y, z]");
    EXPECT_EQ(
        error_of("parts:\n  - sphere: {exact: true}\n    motion: {velocity_mps: [1, 0, 0]}\n"),
        "scene.yaml:3: parts[0].motion: an exact sphere cannot move (drop exact to move the "
        "sphere as triangles)");
    EXPECT_EQ(
        error_of("parts:\n  - mesh: box.obj\n    motion: {keyframes: [{position_m: [1, 2, 3]}]}\n"),
        "scene.yaml:3: parts[0].motion.keyframes[0].time_s: missing");
}

TEST(SceneMotion, MovingPartsComeLastAsInstancesWithTheirObjectsAndFaces) {
    test::TempDir dir;
    // A unit square (2 triangles) in the z = 0 plane.
    test::write_file(dir / "sq.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
    test::write_file(dir / "scene.yaml", R"(parts:
  - {mesh: sq.obj, name: mover, array: {count: [3, 1, 1], step_m: [10, 0, 0]},
     motion: {spin: {axis: [1, 0, 0], rate_rad_s: 1.5707963267948966}}}
  - {mesh: sq.obj, name: still}
  - {plane: {point_m: [0, 0, -1], size_m: 4}, name: ground}
)");
    Scene scene = load_scene_file(dir / "scene.yaml");
    ASSERT_EQ(scene.parts.size(), 3u);
    EXPECT_EQ(scene.parts[0].name, "still");
    EXPECT_EQ(scene.parts[1].name, "ground");
    EXPECT_EQ(scene.parts[2].name, "mover");
    EXPECT_TRUE(scene.parts[2].moving);
    EXPECT_EQ(scene.parts[2].part_id, 1) << "part IDs still follow the file";
    // Still: faces 0-3 (two flat parts, objects 0 and 1); moving: 3 copies of 2 faces.
    EXPECT_EQ(scene.parts[2].first_face, 4u);
    ASSERT_EQ(scene.moving.size(), 3u);
    EXPECT_EQ(scene.moving[2].first_face, 8u);
    EXPECT_EQ(scene.object_of_face(0), 0u);
    EXPECT_EQ(scene.object_of_face(3), 1u);
    EXPECT_EQ(scene.object_of_face(4), 2u);
    EXPECT_EQ(scene.object_of_face(7), 3u);
    EXPECT_EQ(scene.object_of_face(9), 4u);
    // At time 0 the geometry holds every copy where it starts (render, scan).
    EXPECT_EQ(scene.geometry.face_count(), 10u);
    expect_near(scene.geometry.triangle(8)[1], {21, 0, 0}, 1e-12);
    // A quarter turn about +x at 1 s: the square's +z normal turns to -y.
    scene.detach_moving();
    EXPECT_EQ(scene.geometry.face_count(), 4u);
    expect_near(scene.normal_at(8, {20.5, 0, 0}, 0.0), {0, 0, 1}, 1e-12);
    expect_near(scene.normal_at(8, {20.5, 0, 0}, 1.0), {0, -1, 0}, 1e-12);
    expect_near(scene.normal_at(0, {0.5, 0.5, 0}, 1.0), {0, 0, 1}, 1e-12);
    // The point (x, 1, 0) of copy 2 at time 0 moves along +z at 1 m times pi/2.
    expect_near(scene.velocity_at(9, {20.5, 1, 0}, 0.0), {0, 0, kPi / 2}, 1e-12);
    expect_near(scene.velocity_at(1, {0.5, 1, 0}, 0.0), {0, 0, 0}, 0.0);
    scene.detach_moving();  // a second call changes nothing
    EXPECT_EQ(scene.geometry.face_count(), 4u);
}

}  // namespace
}  // namespace beamtrace
