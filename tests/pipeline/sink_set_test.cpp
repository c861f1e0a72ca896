// The survey's sink set: blocks encoded on pool threads in any order (with random delays) reach
// every sink's write() exactly once, in block order; a sink failing at commit aborts the others
// and removes what was already committed, so no output of the run is left.
#include "pipeline/detail/sink_set.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/io/point_sink_registry.hpp"
#include "pipeline/detail/ordered_blocks.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// Encodes a block as "<first pulse>;" and records the writes; optionally fails at commit.
class RecordingSink final : public PointSink {
  public:
    RecordingSink(std::vector<std::string>* written, bool fail_commit)
        : written_(written), fail_commit_(fail_commit) {}
    void encode(const PointBlock& block, SinkBuffer& out) const override {
        static_cast<ByteBuffer&>(out).bytes = std::to_string(block.points.at(0).pulse);
    }
    void write(const SinkBuffer& encoded) override {
        written_->push_back(static_cast<const ByteBuffer&>(encoded).bytes);
    }
    std::vector<std::filesystem::path> commit() override {
        if (fail_commit_) {
            throw OutputError("disk full");
        }
        return {};
    }
    void abort() noexcept override {}

  private:
    std::vector<std::string>* written_;
    bool fail_commit_;
};

TEST(SinkSet, BlocksEncodedInAnyOrderAreWrittenToEverySinkInBlockOrder) {
    constexpr std::size_t kBlocks = 200;
    for (const unsigned threads : {1u, 2u, 4u}) {
        std::vector<std::string> first, second;
        detail::SinkSet sinks;
        sinks.add(std::make_unique<RecordingSink>(&first, false));
        sinks.add(std::make_unique<RecordingSink>(&second, false));
        detail::OrderedBlocks ordered(
            kBlocks, 5, [&](std::size_t, detail::BlockOutput& out) { sinks.write(out); });
        ThreadPool pool(threads);
        pool.parallel_for(kBlocks, 1, [&](std::size_t kb, std::size_t ke) {
            std::mt19937 rng(static_cast<unsigned>(kb));
            PointBlock block;
            block.points.resize(1);
            for (std::size_t k = kb; k < ke; ++k) {
                detail::BlockOutput* out = ordered.acquire(k);
                ASSERT_NE(out, nullptr);
                std::this_thread::sleep_for(std::chrono::microseconds(rng() % 200));
                block.points[0].pulse = k;
                sinks.encode(block, *out);
                ordered.publish(k);
            }
        });
        ordered.finish();
        ASSERT_EQ(first.size(), kBlocks);
        for (std::size_t k = 0; k < kBlocks; ++k) {
            EXPECT_EQ(first[k], std::to_string(k)) << threads << " threads";
        }
        EXPECT_EQ(second, first);
        EXPECT_TRUE(sinks.commit().empty());
    }
}

TEST(SinkSet, ASinkFailingAtCommitLeavesNoOutputOfTheRun) {
    test::TempDir dir;
    SinkFacts facts;
    facts.output_dir = dir.path();
    std::vector<std::string> written;
    detail::SinkSet sinks;
    sinks.add(point_sink("ply").make(facts));
    sinks.add(point_sink("csv").make(facts));
    sinks.add(std::make_unique<RecordingSink>(&written, true));
    sinks.add(std::make_unique<RecordingSink>(&written, false));
    PointBlock block;
    block.points.resize(3);
    detail::BlockOutput out;
    sinks.encode(block, out);
    sinks.write(out);
    EXPECT_THROW((void)sinks.commit(), OutputError);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()))
        << "points.ply and points.csv were committed, then removed";
}

/// What a BesideSink saw at its commit (kept by the test: the set destroys its sinks at commit).
struct BesideCommit {
    bool saw_other = false;
    std::thread::id thread;
};

/// A sink that commits beside the others: at commit it writes `name` in `dir` and waits (at most
/// 10 s) for `other` to be set by a sink committed after it, which only a commit on another
/// thread can see.
class BesideSink final : public PointSink {
  public:
    BesideSink(std::filesystem::path file, std::shared_future<void> other,
               BesideCommit* seen = nullptr)
        : file_(std::move(file)), other_(std::move(other)), seen_(seen) {}
    void encode(const PointBlock& /*block*/, SinkBuffer& /*out*/) const override {}
    void write(const SinkBuffer& /*encoded*/) override {}
    std::vector<std::filesystem::path> commit() override {
        std::ofstream(file_) << "preview";
        const bool saw_other =
            other_.wait_for(std::chrono::seconds(10)) == std::future_status::ready;
        if (seen_ != nullptr) {
            *seen_ = {saw_other, std::this_thread::get_id()};
        }
        return {file_};
    }
    void abort() noexcept override {}
    [[nodiscard]] bool commits_beside() const override { return true; }
    [[nodiscard]] std::vector<std::string> notes() const override { return {"beside"}; }

  private:
    std::filesystem::path file_;
    std::shared_future<void> other_;
    BesideCommit* seen_;
};

/// Sets `done` at commit (and fails when asked), with a note.
class SignallingSink final : public PointSink {
  public:
    SignallingSink(std::promise<void>* done, bool fail) : done_(done), fail_(fail) {}
    void encode(const PointBlock& /*block*/, SinkBuffer& /*out*/) const override {}
    void write(const SinkBuffer& /*encoded*/) override {}
    std::vector<std::filesystem::path> commit() override {
        done_->set_value();
        if (fail_) {
            throw OutputError("disk full");
        }
        return {};
    }
    void abort() noexcept override {}
    [[nodiscard]] std::vector<std::string> notes() const override { return {"signalling"}; }

  private:
    std::promise<void>* done_;
    bool fail_;
};

TEST(SinkSet, ASinkThatCommitsBesideTheOthersOverlapsThemAndKeepsTheOrder) {
    test::TempDir dir;
    std::promise<void> done;
    detail::SinkSet sinks;
    BesideCommit b;
    sinks.add(std::make_unique<BesideSink>(dir.path() / "preview.png", done.get_future(), &b));
    sinks.add(std::make_unique<SignallingSink>(&done, false));
    // Committed one after the other, the first would wait its 10 s for the second in vain.
    const auto files = sinks.commit();
    EXPECT_TRUE(b.saw_other) << "the beside sink's commit did not overlap the other's";
    EXPECT_NE(b.thread, std::this_thread::get_id());
    ASSERT_EQ(files.size(), 1u);
    EXPECT_EQ(files[0], dir.path() / "preview.png");
    EXPECT_TRUE(std::filesystem::exists(files[0]));
    EXPECT_EQ(sinks.notes(), (std::vector<std::string>{"beside", "signalling"}));
}

TEST(SinkSet, ASinkFailingBesideACommittingOneLeavesNoOutputOfTheRun) {
    test::TempDir dir;
    std::promise<void> done;
    detail::SinkSet sinks;
    sinks.add(std::make_unique<BesideSink>(dir.path() / "preview.png", done.get_future()));
    sinks.add(std::make_unique<SignallingSink>(&done, true));
    EXPECT_THROW((void)sinks.commit(), OutputError);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << "preview.png was committed, then removed";
}

TEST(SinkSet, DestroyedBeforeCommitItAbortsEverySink) {
    test::TempDir dir;
    SinkFacts facts;
    facts.output_dir = dir.path();
    {
        detail::SinkSet sinks;
        for (const char* name : {"las", "ply", "csv", "pcd"}) {
            sinks.add(point_sink(name).make(facts));
        }
        PointBlock block;
        block.points.resize(10);
        detail::BlockOutput out;
        sinks.encode(block, out);
        sinks.write(out);
        EXPECT_FALSE(std::filesystem::is_empty(dir.path())) << "temporary files while open";
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace beamtrace
