// ViewJobConfig: the view settings the CLI binds to, their text forms and how the modes combine.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

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
    ASSERT_EQ(job.validate().size(), 1u);  // neither --camera nor --path (the overview): --output
    EXPECT_NE(job.validate()[0].find("--output"), std::string::npos);
    job.output = "overview.png";
    EXPECT_TRUE(job.validate().empty());
    EXPECT_TRUE(job.poses().empty());
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

TEST(ViewJob, OverviewCameraLooksStraightDownAndFitsTheFootprint) {
    ViewCamera base;
    base.width = 320;
    base.height = 180;
    base.hfov_deg = 60.0;
    // Wider in x: facing +y (yaw -90) so that x runs across the image; the footprint's
    // half-width 50 at ground level fills 95 % of the half field of view.
    const ViewCamera c = overview_camera({0, 0, 0}, {100, 50, 20}, base);
    EXPECT_EQ(c.yaw_deg, -90.0);
    EXPECT_EQ(c.pitch_deg, -90.0);
    EXPECT_EQ(c.width, 320);
    EXPECT_NEAR(c.position.x, 50.0, 1e-9);
    EXPECT_NEAR(c.position.y, 25.0, 1e-9);
    const double fit = 50.0 / (std::tan(std::numbers::pi / 6.0) * 0.95);
    EXPECT_NEAR(c.position.z, fit, 1e-6);
    const CameraRays rays(c);
    EXPECT_NEAR(rays.forward().z, -1.0, 1e-12);
    EXPECT_GT(rays.right().x, 0.99);  // image right is +x

    // Longer in y: facing +x (yaw 0), y across the image (image right is -y), fitted on the
    // ground (lo.z = 5), not on the top of the box.
    const ViewCamera t = overview_camera({0, 0, 5}, {50, 200, 9}, base);
    EXPECT_EQ(t.yaw_deg, 0.0);
    EXPECT_LT(CameraRays(t).right().y, -0.99);
    EXPECT_NEAR(t.position.z - 5.0, 100.0 / (std::tan(std::numbers::pi / 6.0) * 0.95), 1e-6);
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
