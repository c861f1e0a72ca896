// The survey's sink set: blocks encoded on pool threads in any order (with random delays) reach
// every sink's write() exactly once, in block order; a sink failing at commit aborts the others
// and removes what was already committed, so no output of the run is left.
#include "pipeline/detail/sink_set.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
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
