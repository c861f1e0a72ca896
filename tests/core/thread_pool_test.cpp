#include "beamtrace/core/thread_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <numeric>
#include <stdexcept>

namespace beamtrace {
namespace {

TEST(ThreadPool, CoversEveryIndexExactlyOnce) {
    for (unsigned threads : {1u, 2u, 5u}) {
        ThreadPool pool(threads);
        EXPECT_EQ(pool.size(), threads);
        for (std::size_t n : {0u, 1u, 7u, 1000u, 100003u}) {
            std::vector<int> hits(n, 0);
            pool.parallel_for(n, 64, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i) {
                    ++hits[i];
                }
            });
            EXPECT_EQ(std::accumulate(hits.begin(), hits.end(), std::size_t{0}), n);
            EXPECT_TRUE(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
        }
    }
}

TEST(ThreadPool, ChunksAreFixedWhateverTheThreadCount) {
    ThreadPool pool(3);
    std::vector<std::pair<std::size_t, std::size_t>> chunks(10);
    pool.parallel_for(1000, 100, [&](std::size_t b, std::size_t e) { chunks[b / 100] = {b, e}; });
    for (std::size_t k = 0; k < 10; ++k) {
        EXPECT_EQ(chunks[k].first, k * 100);
        EXPECT_EQ(chunks[k].second, k * 100 + 100);
    }
}

TEST(ThreadPool, RethrowsTheFirstExceptionAndStaysUsable) {
    ThreadPool pool(4);
    EXPECT_THROW(pool.parallel_for(10000, 10,
                                   [](std::size_t b, std::size_t) {
                                       if (b == 5000) {
                                           throw std::runtime_error("boom");
                                       }
                                   }),
                 std::runtime_error);
    std::atomic<std::size_t> sum{0};
    pool.parallel_for(100, 1, [&](std::size_t b, std::size_t e) { sum += e - b; });
    EXPECT_EQ(sum.load(), 100u);
}

}  // namespace
}  // namespace beamtrace
