// The survey's ordered block writer: blocks filled by pool threads in any order (here with random
// delays) are written exactly once each, in block order, whatever the window and thread count;
// the writer, woken once per batch of blocks, never leaves the producers waiting for room; an
// error in the writer stops the producers and is rethrown.
#include "pipeline/detail/ordered_blocks.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <random>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/core/thread_pool.hpp"

namespace beamtrace {
namespace {

/// Runs `blocks` blocks through OrderedBlocks as the survey does; returns what was written.
std::vector<std::string> run_blocks(std::size_t blocks, std::size_t window, unsigned threads,
                                    std::size_t fail_at = ~std::size_t{0}) {
    std::vector<std::string> written;
    detail::OrderedBlocks ordered(blocks, window, [&](std::size_t k, detail::BlockOutput& out) {
        if (k == fail_at) {
            throw std::runtime_error("disk full at " + std::to_string(k));
        }
        written.push_back(static_cast<const ByteBuffer&>(*out.sinks.at(0)).bytes);
    });
    ThreadPool pool(threads);
    pool.parallel_for(blocks, 1, [&](std::size_t kb, std::size_t ke) {
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

TEST(OrderedBlocks, EveryBlockIsWrittenOnceInOrderWhateverTheWindowAndThreads) {
    // Windows below, at and above the writer's wake batch (8), and a window of one block.
    for (const std::size_t window : {1, 2, 3, 8, 9, 64}) {
        for (const unsigned threads : {1u, 2u, 4u}) {
            for (const std::size_t blocks : {1, 7, 8, 100}) {
                const std::vector<std::string> written = run_blocks(blocks, window, threads);
                ASSERT_EQ(written.size(), blocks)
                    << "window " << window << ", " << threads << " threads";
                for (std::size_t k = 0; k < blocks; ++k) {
                    EXPECT_EQ(written[k], "block " + std::to_string(k));
                }
            }
        }
    }
}

TEST(OrderedBlocks, AWriterErrorStopsTheProducersAndIsRethrown) {
    try {
        static_cast<void>(run_blocks(200, 4, 3, 17));
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "disk full at 17");
    }
}

}  // namespace
}  // namespace beamtrace
