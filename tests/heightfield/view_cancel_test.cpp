// Cancellation of run_view_frames: a CancelToken requested after a frame was written makes it
// throw Interrupted, remove the frames it wrote and the folder it created.
#include <gtest/gtest.h>

#include <csignal>

#include "beamtrace/core/cancel.hpp"
#include "beamtrace/heightfield/view_job.hpp"
#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

class ViewCancel : public test::TempDirTest {};

TEST_F(ViewCancel, AnInterruptedFlyThroughRemovesItsFramesAndFolder) {
    const auto las = test::write_bridge_las(dir_ / "bridge.las");
    CancelToken token;
    ViewJobConfig job;
    job.inputs = {las};
    job.session = test::bridge_view_config(0);
    job.camera.width = 41;
    job.camera.height = 21;
    job.path = "unused.csv";
    job.output = dir_ / "new" / "frames";
    job.cancel = &token;
    const std::vector<CameraPose> poses = {
        {{2, 16.3, 4}, 0, -10}, {{30, 16.3, 6}, 180, -15}, {{10, 16.3, 5}, 90, -20}};
    ViewSession session(job.inputs, job.session);
    std::size_t written = 0;
    bool frame_there = false;
    ViewFrameHooks hooks;
    hooks.written = [&](const ViewFrame& f) {
        ++written;
        frame_there = std::filesystem::exists(f.file);
        if (f.index == 1) {
            token.request(SIGINT);
        }
    };
    EXPECT_THROW((void)run_view_frames(job, session, poses, hooks), Interrupted);
    EXPECT_EQ(written, 2u);
    EXPECT_TRUE(frame_there);
    EXPECT_FALSE(std::filesystem::exists(dir_ / "new"));

    // Without a request the same call writes every frame.
    CancelToken unused;
    job.cancel = &unused;
    written = 0;
    (void)run_view_frames(job, session, poses, hooks);
    EXPECT_EQ(test::entry_count(job.output), 3u);
}

}  // namespace
}  // namespace beamtrace
