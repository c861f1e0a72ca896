// ViewJobConfig: the view settings the CLI binds to, their text forms and how the modes combine.
#include <gtest/gtest.h>

#include <string>

#include "beamtrace/core/error.hpp"
#include "beamtrace/heightfield/view_job.hpp"
#include "beamtrace/io/png_reader.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(ViewJob, ParsesSizesAndByteSizes) {
    EXPECT_EQ(parse_byte_size("1GB"), 1'000'000'000u);
    EXPECT_EQ(parse_byte_size("256MB"), 256'000'000u);
    EXPECT_EQ(parse_byte_size("512MiB"), 512u * 1024u * 1024u);
    EXPECT_EQ(parse_byte_size("1.5GiB"), 3u * 512u * 1024u * 1024u);
    EXPECT_EQ(parse_byte_size("1000"), 1000u);
    for (const char* bad : {"lots", "", "-1GB", "0", "2TB", "GB"}) {
        EXPECT_THROW(static_cast<void>(parse_byte_size(bad)), ConfigError) << bad;
    }
    EXPECT_EQ(byte_size_text(1'000'000'000), "1GB");
    EXPECT_EQ(byte_size_text(45'000'000), "45MB");
    EXPECT_EQ(byte_size_text(1023), "1023");
    EXPECT_EQ(parse_byte_size(byte_size_text(HeightFieldConfig{}.memory_budget_bytes)),
              HeightFieldConfig{}.memory_budget_bytes);
    int w = 0, h = 0;
    parse_size_pair("240x135", "--size", w, h);
    EXPECT_EQ(w, 240);
    EXPECT_EQ(h, 135);
    for (const char* bad : {"240", "0x5", "5x", "x5", "ax5", "4x-2", "240x135x2"}) {
        EXPECT_THROW(parse_size_pair(bad, "--size", w, h), ConfigError) << bad;
    }
    EXPECT_EQ(parse_section_window("3x3"), 3);
    EXPECT_THROW(static_cast<void>(parse_section_window("3x4")), ConfigError);
}

TEST(ViewJob, ModesCombineOneWay) {
    ViewJobConfig job;
    ASSERT_EQ(job.validate().size(), 2u);  // neither --camera nor --path, and no --output
    job.pose = CameraPose{{1, 2, 3}, 10, -20};
    job.output = "x.png";
    EXPECT_TRUE(job.validate().empty());
    ASSERT_EQ(job.poses().size(), 1u);
    EXPECT_EQ(job.poses()[0].yaw_deg, 10.0);
    job.path = "path.csv";  // both
    EXPECT_FALSE(job.validate().empty());
    job.path.clear();
    job.frames = 3;  // --frames without --interactive
    ASSERT_EQ(job.validate().size(), 1u);
    EXPECT_NE(job.validate()[0].find("--interactive"), std::string::npos);
    job.interactive = true;
    job.output.clear();
    EXPECT_TRUE(job.validate().empty());
    job.mp4 = "fly.mp4";  // a video needs a path
    EXPECT_FALSE(job.validate().empty());

    ViewJobConfig live;
    live.interactive = true;
    EXPECT_TRUE(live.validate().empty());
    EXPECT_TRUE(live.poses().empty());
}

TEST(ViewJob, OverviewCameraLooksDownAlongXFromAboveTheData) {
    ViewCamera base;
    base.width = 320;
    const ViewCamera c = overview_camera({0, 0, 0}, {100, 50, 20}, base);
    EXPECT_EQ(c.position, (Vec3d{20, 25, 30}));
    EXPECT_EQ(c.yaw_deg, 0.0);
    EXPECT_EQ(c.pitch_deg, -30.0);
    EXPECT_EQ(c.width, 320);
    EXPECT_GT(CameraRays(c).forward().x, 0.0);
}

class ViewFrames : public test::TempDirTest {};

TEST_F(ViewFrames, WritesOnePngPerPoseEqualToTheSessionsRender) {
    const auto las = test::write_bridge_las(dir_ / "bridge.las");
    ViewJobConfig job;
    job.inputs = {las};
    job.session = test::bridge_view_config(0);
    job.camera.width = 41;
    job.camera.height = 21;
    job.path = "unused.csv";  // a fly-through: frames into a folder
    job.output = dir_ / "frames";
    const std::vector<CameraPose> poses = {{{2, 16.3, 4}, 0, -10}, {{30, 16.3, 6}, 180, -15}};
    ViewSession session(job.inputs, job.session);
    std::vector<std::size_t> written;
    ViewFrameHooks hooks;
    hooks.written = [&](const ViewFrame& f) { written.push_back(f.index); };
    const ViewFramesResult r = run_view_frames(job, session, poses, hooks);
    EXPECT_EQ(r.frames, 2u);
    EXPECT_EQ(written, (std::vector<std::size_t>{0, 1}));
    EXPECT_EQ(r.mp4_frames, 0);
    for (std::size_t i = 0; i < poses.size(); ++i) {
        ViewSession fresh(job.inputs, job.session);
        ViewCamera cam = job.camera;
        cam.set_pose(poses[i]);
        static_cast<void>(fresh.move_to(cam.position));
        const RgbImage png =
            read_png_rgb8(job.output / ("frame_0000" + std::to_string(i) + ".png"));
        EXPECT_EQ(png.rgb, fresh.render(cam, job.render).rgb) << "frame " << i;
    }
}

}  // namespace
}  // namespace beamtrace
