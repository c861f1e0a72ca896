// Background loading of sections: frames rendered after a prefetch equal frames rendered after a
// synchronous move_to, pixel for pixel, and the memory budget holds with the prefetched sections.
#include "beamtrace/heightfield/view_session.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "heightfield/heightfield_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// A path across autzen_trim.las (x 636002..637179 ft, y 848935..849498 ft), 64 ft sections.
class ViewPrefetch : public ::testing::Test {
  protected:
    void SetUp() override {
        path_ = test::shared_data("las/las/autzen_trim.las");
        BEAMTRACE_REQUIRE_FILE(path_);
        for (int i = 0; i < 14; ++i) {
            poses_.push_back({636050.0 + 85.0 * i, 849150.0 + 9.0 * i, 500.0});
        }
    }

    /// 3 x 3 windows of 64 ft sections; the budget holds `sections` of them and the buffer.
    [[nodiscard]] static ViewSessionConfig config(int sections) {
        ViewSessionConfig c;
        c.field.cell_size = 2.0;
        c.field.levels = 4;
        c.field.section_cells = 4;
        c.field.sections = 3;
        c.field.color = ColorMode::intensity;
        c.ingest.block_bytes = 64 << 10;
        c.field.memory_budget_bytes =
            c.ingest.block_bytes +
            static_cast<std::uint64_t>(sections) * HeightSection::bytes_for(c.field.layout(), true);
        c.threads = 2;
        return c;
    }

    [[nodiscard]] static ViewCamera camera(const Vec3d& p, int i) {
        ViewCamera cam;
        cam.position = p;
        cam.yaw_deg = 10.0 * i;
        cam.pitch_deg = -60.0;
        cam.hfov_deg = 70.0;
        cam.width = 96;
        cam.height = 54;
        return cam;
    }

    [[nodiscard]] std::vector<ViewImage> synchronous(const ViewSessionConfig& c) const {
        ViewSession session(std::span(&path_, 1), c);
        std::vector<ViewImage> frames;
        for (std::size_t i = 0; i < poses_.size(); ++i) {
            static_cast<void>(session.move_to(poses_[i]));
            frames.push_back(session.render(camera(poses_[i], static_cast<int>(i)), {}));
        }
        return frames;
    }

    std::filesystem::path path_;
    std::vector<Vec3d> poses_;
};

TEST_F(ViewPrefetch, PrefetchedFramesEqualSynchronousFramesWithinTheBudget) {
    // 12 sections: room for the next column of the window next to the resident ones; 6: the
    // window does not fit, so prefetching finds little or no room and move_to loads the rest.
    for (const int sections : {12, 6}) {
        SCOPED_TRACE("budget of " + std::to_string(sections) + " sections");
        const ViewSessionConfig c = config(sections);
        const std::vector<ViewImage> expected = synchronous(c);
        ViewSession session(std::span(&path_, 1), c);
        static_cast<void>(session.move_to(poses_[0]));
        int prefetched = 0, loaded = 0;
        std::size_t hits = 0;
        ViewImage frame;
        for (std::size_t i = 0; i < poses_.size(); ++i) {
            if (i + 1 < poses_.size()) {
                session.prefetch(poses_[i + 1]);  // loads while frame i renders
                EXPECT_LE(session.budgeted_bytes(), c.field.memory_budget_bytes);
            }
            session.render(camera(poses_[i], static_cast<int>(i)), {}, frame);
            std::string first;
            EXPECT_EQ(test::count_mismatches(frame, expected[i], first), 0u)
                << "frame " << i << ": " << first;
            EXPECT_EQ(frame.rgb, expected[i].rgb) << "frame " << i;
            hits += frame.hits();
            if (i + 1 < poses_.size()) {
                const IngestStats s = session.move_to(poses_[i + 1]);
                prefetched += s.sections_prefetched;
                loaded += s.sections_loaded;
                EXPECT_LE(session.budgeted_bytes(), c.field.memory_budget_bytes);
            }
        }
        EXPECT_LE(session.peak_budgeted_bytes(), c.field.memory_budget_bytes);
        EXPECT_GT(hits, poses_.size() * 96 * 54 / 4);  // the frames show the data
        if (sections == 12) {
            EXPECT_GE(prefetched, 10) << "sections loaded in the foreground: " << loaded;
        }
        EXPECT_GT(prefetched + loaded, 10);
    }
}

TEST_F(ViewPrefetch, NonBlockingUpdatesConvergeToTheSynchronousFrame) {
    const ViewSessionConfig c = config(7);
    ViewSession sync(std::span(&path_, 1), c);
    ViewSession live(std::span(&path_, 1), c);
    for (const std::size_t i :
         {std::size_t{0}, std::size_t{1}, std::size_t{6}, std::size_t{13}, std::size_t{2}}) {
        static_cast<void>(sync.move_to(poses_[i]));
        const ViewCamera cam = camera(poses_[i], static_cast<int>(i));
        const ViewImage expected = sync.render(cam, {});
        // A frame loop: never waits; renders whatever is loaded.
        int frames = 0;
        for (; frames < 2000; ++frames) {
            static_cast<void>(live.update(cam.position));
            EXPECT_LE(live.budgeted_bytes(), c.field.memory_budget_bytes);
            const LoadStatus status = live.load_status();
            EXPECT_LE(status.points_done, status.points_total);
            if (status.sections == 0) {
                break;  // nothing in flight and nothing missing
            }
            static_cast<void>(live.render(cam, {}));
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        ASSERT_LT(frames, 2000);
        const ViewImage got = live.render(cam, {});
        std::string first;
        EXPECT_EQ(test::count_mismatches(got, expected, first), 0u)
            << "pose " << i << ": " << first;
        EXPECT_EQ(live.grid().loaded_sections(), sync.grid().loaded_sections());
    }
    EXPECT_LE(live.peak_budgeted_bytes(), c.field.memory_budget_bytes);
}

TEST_F(ViewPrefetch, LookAheadLoadsTheWindowAheadAsSparesAndShowsThemWhenReached) {
    // Room for the 3 x 3 window and 3 sections more: a column of the window ahead.
    const ViewSessionConfig c = config(12);
    ViewSession live(std::span(&path_, 1), c);
    ViewSession sync(std::span(&path_, 1), c);
    const Vec3d here = poses_[4];
    const Vec3d ahead = here + Vec3d{64.0, 0.0, 0.0};  // one section along +x
    const auto settle = [&](const Vec3d& at, const Vec3d& next) {
        for (int frames = 0; frames < 2000; ++frames) {
            static_cast<void>(live.update(at, next));
            EXPECT_LE(live.budgeted_bytes(), c.field.memory_budget_bytes);
            if (live.load_status().sections == 0) {
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        FAIL() << "loads did not settle";
    };
    settle(here, ahead);
    // The window here is complete and the column ahead was loaded aside.
    static_cast<void>(sync.move_to(here));
    EXPECT_EQ(live.grid().loaded_sections(), sync.grid().loaded_sections());
    EXPECT_EQ(live.spare_sections(), 3);
    // Reaching it shows those sections at once: no load is needed for the new window.
    EXPECT_TRUE(live.update(ahead, ahead));
    EXPECT_EQ(live.load_status().sections, 0);
    static_cast<void>(sync.move_to(ahead));
    EXPECT_EQ(live.grid().loaded_sections(), sync.grid().loaded_sections());
    const ViewCamera cam = camera(ahead, 3);
    std::string first;
    EXPECT_EQ(test::count_mismatches(live.render(cam, {}), sync.render(cam, {}), first), 0u)
        << first;
    // Turning back: the spares (the column left behind) make room for the camera's window,
    // and the frame converges to the synchronous one within the budget.
    settle(poses_[1], poses_[1]);
    static_cast<void>(sync.move_to(poses_[1]));
    const ViewCamera back = camera(poses_[1], 1);
    EXPECT_EQ(test::count_mismatches(live.render(back, {}), sync.render(back, {}), first), 0u)
        << first;
    EXPECT_LE(live.peak_budgeted_bytes(), c.field.memory_budget_bytes);
}

}  // namespace
}  // namespace beamtrace
