// Progressive refinement of the interactive view: the pixel step chosen from the frame times,
// the stepped camera, and the frame-time summary.
#include "beamtrace/heightfield/view_progressive.hpp"

#include <gtest/gtest.h>

#include "beamtrace/heightfield/view_job.hpp"

namespace beamtrace {
namespace {

TEST(ViewProgressive, StepIsTheSmallestThatFitsTheMovingFrameTime) {
    ProgressiveConfig config;  // 33 ms, steps up to 4
    ProgressiveScaler scaler(config);
    EXPECT_EQ(scaler.step(true, 1280, 720), 1) << "no estimate yet";
    // 66 ms to render the full frame (921 600 pixels), 4 ms more to draw it. Step 2 has
    // 230 400 pixels: 16.5 + 4 ms, fits; step 1 (70 ms) does not.
    scaler.record(1280 * 720, 0.066, 0.070);
    EXPECT_DOUBLE_EQ(scaler.seconds_per_pixel(), 0.066 / (1280.0 * 720.0));
    EXPECT_DOUBLE_EQ(scaler.overhead_seconds(), 0.004);
    EXPECT_EQ(scaler.step(true, 1280, 720), 2);
    EXPECT_EQ(scaler.step(false, 1280, 720), 1) << "a still camera gets the full frame";
    // A frame of step 2 took 40 ms to render (173.6 ns a pixel) and 48 ms in all: the
    // estimates are the means, 123.6 ns a pixel and 6 ms: step 2 needs 28.5 + 6 ms, too much;
    // step 3 (427 x 240 = 102 480 pixels) 12.7 + 6 ms fits.
    scaler.record(640 * 360, 0.040, 0.048);
    const double per_pixel = 0.5 * (0.066 / (1280.0 * 720.0) + 0.040 / (640.0 * 360.0));
    EXPECT_DOUBLE_EQ(scaler.seconds_per_pixel(), per_pixel);
    EXPECT_DOUBLE_EQ(scaler.overhead_seconds(), 0.006);
    EXPECT_EQ(scaler.step(true, 1280, 720), 3);
    // Without the time outside the render, step 2 would have fitted.
    ProgressiveScaler render_only(config);
    render_only.record(1280 * 720, 0.066, 0.066);
    render_only.record(640 * 360, 0.040, 0.040);
    EXPECT_EQ(render_only.step(true, 1280, 720), 2);
    // Far too slow: even step 3 exceeds 33 ms; the coarsest is 4.
    scaler.record(1280 * 720, 10.0, 10.0);
    EXPECT_EQ(scaler.step(true, 1280, 720), 4);
    // Drawing alone takes longer than the aim: the coarsest step.
    ProgressiveScaler slow_draw(config);
    slow_draw.record(1280 * 720, 0.001, 0.101);
    EXPECT_EQ(slow_draw.step(true, 1280, 720), 4);
    // Fast: full resolution while moving too.
    ProgressiveScaler fast(config);
    fast.record(1280 * 720, 0.010, 0.012);
    EXPECT_EQ(fast.step(true, 1280, 720), 1);
    // Ignored: empty frames and zero times.
    fast.record(0, 1.0, 1.0);
    fast.record(100, 0.0, 1.0);
    EXPECT_DOUBLE_EQ(fast.seconds_per_pixel(), 0.010 / (1280.0 * 720.0));
    EXPECT_DOUBLE_EQ(fast.overhead_seconds(), 0.002);
}

TEST(ViewProgressive, ZeroMovingFrameTimeKeepsFullResolution) {
    ProgressiveConfig config;
    config.moving_frame_s = 0.0;
    ProgressiveScaler scaler(config);
    scaler.record(1280 * 720, 10.0, 10.0);
    EXPECT_EQ(scaler.step(true, 1280, 720), 1);
}

TEST(ViewProgressive, SteppedCameraKeepsThePoseAndRoundsTheSizeUp) {
    ViewCamera c;
    c.position = {1, 2, 3};
    c.yaw_deg = 30;
    c.pitch_deg = -20;
    c.hfov_deg = 70;
    c.width = 1280;
    c.height = 721;
    const ViewCamera s = stepped_camera(c, 3);
    EXPECT_EQ(s.width, 427);
    EXPECT_EQ(s.height, 241);
    EXPECT_EQ(s.position.x, 1.0);
    EXPECT_EQ(s.yaw_deg, 30.0);
    EXPECT_EQ(s.pitch_deg, -20.0);
    EXPECT_EQ(s.hfov_deg, 70.0);
    EXPECT_EQ(stepped_camera(c, 1).width, 1280);
}

TEST(ViewProgressive, SummaryIsTheMedianAndTheNearestRank95thPercentile) {
    EXPECT_EQ(summarize_frame_times({}).frames, 0u);
    std::vector<double> ms;
    for (int i = 20; i >= 1; --i) {
        ms.push_back(i);  // 1..20, reversed
    }
    const FrameTimeSummary s = summarize_frame_times(ms);
    EXPECT_EQ(s.frames, 20u);
    EXPECT_DOUBLE_EQ(s.median_ms, 10.5);
    EXPECT_DOUBLE_EQ(s.p95_ms, 19.0);  // rank ceil(0.95 * 20) = 19
    EXPECT_DOUBLE_EQ(s.fps(), 1e3 / 10.5);
    const FrameTimeSummary one = summarize_frame_times({7.0});
    EXPECT_DOUBLE_EQ(one.median_ms, 7.0);
    EXPECT_DOUBLE_EQ(one.p95_ms, 7.0);
}

TEST(ViewProgressive, BadSettingsAreConfigProblemsOfTheWindowOnly) {
    ViewJobConfig job;
    job.interactive = true;
    job.progressive.moving_frame_s = -1.0;
    job.progressive.max_step = 9;
    const auto problems = job.validate();
    ASSERT_EQ(problems.size(), 2u);
    EXPECT_NE(problems[0].find("--moving-frame-s"), std::string::npos);
    EXPECT_NE(problems[1].find("--max-pixel-step 9"), std::string::npos);
    job.progressive = {};
    job.path = "flight.csv";  // a scripted flight
    EXPECT_TRUE(job.validate().empty());
    job.pose = CameraPose{{1, 2, 3}, 0, 0};
    EXPECT_EQ(job.validate().size(), 1u) << "--camera and --path";
    job.pose.reset();
    job.mp4 = "x.mp4";
    EXPECT_EQ(job.validate().size(), 1u) << "--mp4 with the window";
    ViewJobConfig offline;
    offline.output = "x.png";
    offline.frame_log = "frames.csv";
    ASSERT_EQ(offline.validate().size(), 1u);
    EXPECT_NE(offline.validate()[0].find("--frame-log"), std::string::npos);
}

}  // namespace
}  // namespace beamtrace
