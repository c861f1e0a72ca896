// One camera convention (docs/camera.md): the same `--camera X,Y,Z,YAW,PITCH` text gives the same
// viewing direction in `view` (the height-field camera) and `render` (the shaded-image camera),
// and that direction is the one every other roll-pitch-yaw of beamtrace gives (rpy_matrix, as
// survey files' rotate_deg and scan --orientation use it).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/core/camera_pose.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/core/rotation.hpp"
#include "beamtrace/heightfield/view_camera.hpp"
#include "beamtrace/pipeline/render_job.hpp"
#include "beamtrace/render/camera.hpp"

namespace beamtrace {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

void expect_near(const Vec3d& a, const Vec3d& b, const std::string& what) {
    EXPECT_NEAR(a.x, b.x, 1e-12) << what;
    EXPECT_NEAR(a.y, b.y, 1e-12) << what;
    EXPECT_NEAR(a.z, b.z, 1e-12) << what;
}

TEST(CameraConvention, ViewAndRenderLookTheSameWayForTheSameCameraText) {
    for (const std::string text : {"1,2,3,0,0", "0,0,10,90,0", "5,-4,2,30,-60", "0,0,0,-135,20",
                                   "7,7,7,200,-90", "1,1,1,310.5,45"}) {
        SCOPED_TRACE(text);
        RenderJobConfig job;
        job.set_camera(text);
        CameraConfig rc = job.render.camera;
        rc.position_m = *job.camera_position_m;
        const Vec3d render_forward = Camera(rc).forward();

        ViewCamera vc;
        vc.set_pose(parse_camera_pose(text, "--camera").pose);
        const Vec3d view_forward = CameraRays(vc).forward();

        expect_near(render_forward, view_forward, "view vs render");
        expect_near(view_forward, vc.pose().forward(), "view vs CameraPose::forward");
        expect_near(render_forward, sensor_to_world({1, 0, 0}, rpy_matrix(vc.pose().orientation())),
                    "render vs rpy_matrix");
    }
}

TEST(CameraConvention, PositiveYawPansRightAndPositivePitchTiltsUp) {
    CameraPose p;
    p.yaw_deg = 90.0;  // clockwise seen from above: from +x towards -y
    expect_near(p.forward(), {0, -1, 0}, "yaw 90");
    p.yaw_deg = -90.0;
    expect_near(p.forward(), {0, 1, 0}, "yaw -90");
    p = {};
    p.pitch_deg = -90.0;
    expect_near(p.forward(), {0, 0, -1}, "pitch -90");
    p.pitch_deg = 30.0;
    expect_near(p.forward(), {std::cos(30 * kDeg), 0, std::sin(30 * kDeg)}, "pitch 30");
    // The height-field image's right is horizontal and 90 degrees clockwise of the yaw.
    ViewCamera vc;
    vc.yaw_deg = 0.0;
    vc.pitch_deg = -40.0;
    vc.width = vc.height = 3;
    const Vec3d right_edge = CameraRays(vc).direction(2, 1);
    EXPECT_LT(right_edge.y, 0.0);  // looking along +x, the right is -y
}

TEST(CameraConvention, ParsesTheFormsEachCommandTakes) {
    const ParsedCameraPose p = parse_camera_pose(" 1, 2 ,3,45,-10 ", "--camera");
    EXPECT_EQ(p.pose.position, (Vec3d{1, 2, 3}));
    EXPECT_EQ(p.pose.yaw_deg, 45.0);
    EXPECT_EQ(p.pose.pitch_deg, -10.0);
    EXPECT_TRUE(p.has_angles);
    EXPECT_TRUE(p.extra.empty());
    for (const char* bad : {"1,2,3", "1,2,3,4", "1,2,3,4,5,6", "1,2,3,a,5", "1,2,3,4,inf", ""}) {
        EXPECT_THROW(static_cast<void>(parse_camera_pose(bad, "--camera")), ConfigError) << bad;
    }
    const ParsedCameraPose q =
        parse_camera_pose("1,2,3", "--camera", {.position_only = true, .max_extra = 1});
    EXPECT_FALSE(q.has_angles);
    const ParsedCameraPose r =
        parse_camera_pose("1,2,3,4,5,6", "--camera", {.position_only = true, .max_extra = 1});
    ASSERT_EQ(r.extra.size(), 1u);
    EXPECT_EQ(r.extra[0], 6.0);
    std::string why;
    EXPECT_FALSE(try_parse_camera_pose("1,2,x,4,5", {}, why));
    EXPECT_NE(why.find("field 3 'x'"), std::string::npos) << why;
}

TEST(CameraConvention, RenderLookAtNeedsOnlyThePosition) {
    RenderJobConfig job;
    job.scene = "scene.yaml";
    job.set_camera("-6,-4,3");
    EXPECT_FALSE(job.validate().empty()) << "X,Y,Z alone needs --look-at";
    job.set_look_at("0,0,0.8");
    EXPECT_TRUE(job.validate().empty());
    EXPECT_THROW(job.set_look_at("0,0,0.8,1,2"), ConfigError);
    RenderJobConfig no_position;
    no_position.scene = "scene.yaml";
    no_position.set_look_at("0,0,0");
    ASSERT_FALSE(no_position.validate().empty());
    EXPECT_NE(no_position.validate().front().find("--look-at needs --camera"), std::string::npos);
    // The library default image size is the CLI's.
    EXPECT_EQ(CameraConfig{}.width, 640);
    EXPECT_EQ(CameraConfig{}.height, 480);
}

}  // namespace
}  // namespace beamtrace
