// The survey's ordered block writer: blocks filled by pool threads in any order (here with random
// delays) are written exactly once each, in block order, whatever the window, thread count and
// writer (the pool threads combining, or a thread of its own woken once per batch of blocks),
// never leaving the producers waiting for room; combining writes on the pool's own threads, one
// at a time; an error in a write stops the producers and is rethrown.
#include "pipeline/detail/ordered_blocks.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"

namespace beamtrace {
namespace {

/// Runs `blocks` blocks through OrderedBlocks as the survey does; returns what was written.
/// What the writes saw: the threads they ran on, the most at once.
struct WriteThreads {
    std::set<std::thread::id> writers, producers;
    int most_at_once = 0;
};

std::vector<std::string> run_blocks(std::size_t blocks, std::size_t window, unsigned threads,
                                    detail::BlockWriter mode, std::size_t fail_at = ~std::size_t{0},
                                    WriteThreads* seen = nullptr) {
    std::vector<std::string> written;
    std::mutex mutex;
    WriteThreads local;
    WriteThreads& w = seen != nullptr ? *seen : local;
    std::atomic<int> at_once{0};
    const auto write = [&](std::size_t k, detail::BlockOutput& out) {
        const int now = ++at_once;
        {
            const std::lock_guard lock(mutex);
            w.writers.insert(std::this_thread::get_id());
            w.most_at_once = std::max(w.most_at_once, now);
        }
        std::this_thread::sleep_for(std::chrono::microseconds(k % 3 == 0 ? 50 : 0));
        --at_once;
        if (k == fail_at) {
            throw std::runtime_error("disk full at " + std::to_string(k));
        }
        written.push_back(static_cast<const ByteBuffer&>(*out.sinks.at(0)).bytes);
    };
    detail::OrderedBlocks ordered(blocks, window, write, mode);
    ThreadPool pool(threads);
    pool.parallel_for(blocks, 1, [&](std::size_t kb, std::size_t ke) {
        {
            const std::lock_guard lock(mutex);
            w.producers.insert(std::this_thread::get_id());
        }
        std::mt19937 rng(static_cast<unsigned>(kb));
        for (std::size_t k = kb; k < ke; ++k) {
            detail::BlockOutput* out = ordered.acquire(k);
            if (out == nullptr) {
                return;
            }
            std::this_thread::sleep_for(std::chrono::microseconds(rng() % 300));
            if (out->sinks.empty()) {
                out->sinks.push_back(std::make_unique<ByteBuffer>());
            }
            static_cast<ByteBuffer&>(*out->sinks[0]).bytes = "block " + std::to_string(k);
            ordered.publish(k);
        }
    });
    ordered.finish();
    return written;
}

constexpr detail::BlockWriter kModes[] = {detail::BlockWriter::combining,
                                          detail::BlockWriter::own_thread};

const char* name(detail::BlockWriter mode) {
    return mode == detail::BlockWriter::combining ? "combining" : "own thread";
}

TEST(OrderedBlocks, EveryBlockIsWrittenOnceInOrderWhateverTheWindowAndThreads) {
    // Windows below, at and above the writer's wake batch (8), and a window of one block.
    for (const detail::BlockWriter mode : kModes) {
        for (const std::size_t window : {1, 2, 3, 8, 9, 64}) {
            for (const unsigned threads : {1u, 2u, 4u}) {
                for (const std::size_t blocks : {1, 7, 8, 100}) {
                    const std::vector<std::string> written =
                        run_blocks(blocks, window, threads, mode);
                    ASSERT_EQ(written.size(), blocks)
                        << name(mode) << ", window " << window << ", " << threads << " threads";
                    for (std::size_t k = 0; k < blocks; ++k) {
                        EXPECT_EQ(written[k], "block " + std::to_string(k)) << name(mode);
                    }
                }
            }
        }
    }
}

TEST(OrderedBlocks, CombiningWritesOnThePoolThreadsOneAtATime) {
    for (const unsigned threads : {1u, 2u, 4u}) {
        WriteThreads seen;
        const auto written =
            run_blocks(300, 6, threads, detail::BlockWriter::combining, ~std::size_t{0}, &seen);
        ASSERT_EQ(written.size(), 300u);
        EXPECT_EQ(seen.most_at_once, 1) << threads << " threads";
        for (const std::thread::id id : seen.writers) {
            EXPECT_EQ(seen.producers.count(id), 1u) << "a write ran off the pool's threads";
        }
    }
    // Its own thread: every write there, none on the pool's.
    WriteThreads seen;
    (void)run_blocks(100, 6, 2, detail::BlockWriter::own_thread, ~std::size_t{0}, &seen);
    ASSERT_EQ(seen.writers.size(), 1u);
    EXPECT_EQ(seen.producers.count(*seen.writers.begin()), 0u);
}

// behind(k): the blocks before k taken but not yet written (the survey's writer thread encodes
// blocks only while this stays under half the window).
TEST(OrderedBlocks, BehindCountsTheBlocksBeforeKNotYetWritten) {
    std::vector<std::size_t> written;
    detail::OrderedBlocks ordered(
        5, 8, [&](std::size_t k, detail::BlockOutput& /*out*/) { written.push_back(k); },
        detail::BlockWriter::combining);
    for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_NE(ordered.acquire(k), nullptr);
    }
    EXPECT_EQ(ordered.behind(0), 0u);
    EXPECT_EQ(ordered.behind(3), 3u);
    ordered.publish(1);  // not the next in order: nothing written yet
    EXPECT_EQ(ordered.behind(3), 3u);
    ordered.publish(0);  // blocks 0 and 1 written
    EXPECT_EQ(ordered.behind(3), 1u);
    EXPECT_EQ(ordered.behind(1), 0u);
    ordered.publish(2);
    EXPECT_EQ(ordered.behind(3), 0u);
    for (std::size_t k = 3; k < 5; ++k) {
        ASSERT_NE(ordered.acquire(k), nullptr);
        ordered.publish(k);
    }
    ordered.finish();
    EXPECT_EQ(written, (std::vector<std::size_t>{0, 1, 2, 3, 4}));
}

TEST(OrderedBlocks, BehindCountsBlocksReadyButNotYetWrittenByTheWriterThread) {
    std::atomic<std::size_t> writes{0};
    // A window of 8: the writer thread sleeps until 8 blocks are ready in order, or all 5.
    detail::OrderedBlocks ordered(
        5, 8, [&](std::size_t /*k*/, detail::BlockOutput& /*out*/) { ++writes; },
        detail::BlockWriter::own_thread);
    for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_NE(ordered.acquire(k), nullptr);
        ordered.publish(k);
    }
    EXPECT_EQ(ordered.behind(3), 3u);  // ready in order, still asleep
    EXPECT_EQ(writes.load(), 0u);
    for (std::size_t k = 3; k < 5; ++k) {
        ASSERT_NE(ordered.acquire(k), nullptr);
        ordered.publish(k);
    }
    ordered.finish();
    EXPECT_EQ(writes.load(), 5u);
    EXPECT_EQ(ordered.behind(5), 0u);
}

TEST(OrderedBlocks, AWriterErrorStopsTheProducersAndIsRethrown) {
    for (const detail::BlockWriter mode : kModes) {
        for (const unsigned threads : {1u, 3u}) {
            try {
                static_cast<void>(run_blocks(200, 4, threads, mode, 17));
                FAIL() << "no error: " << name(mode);
            } catch (const std::runtime_error& e) {
                EXPECT_EQ(std::string(e.what()), "disk full at 17") << name(mode);
            }
        }
    }
}

}  // namespace
}  // namespace beamtrace
