#include "beamtrace/core/thread_pool.hpp"

#include <gtest/gtest.h>
#include <sched.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <numeric>
#include <stdexcept>

namespace beamtrace {
namespace {

// The default pool follows the process's CPU affinity (taskset, cpusets, an MPI rank's binding),
// not the machine's hardware threads: bound to one core, in a forked child, it is one thread.
TEST(ThreadPool, DefaultSizeIsTheCoresTheProcessMayRunOn) {
    cpu_set_t set;
    CPU_ZERO(&set);
    ASSERT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
    EXPECT_EQ(available_cores(), static_cast<unsigned>(CPU_COUNT(&set)));
    EXPECT_EQ(ThreadPool().size(), available_cores());
    int first = 0;
    while (!CPU_ISSET(first, &set)) {
        ++first;
    }
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(first, &one);
        if (sched_setaffinity(0, sizeof one, &one) != 0) {
            ::_exit(10);
        }
        ::_exit(available_cores() == 1 && ThreadPool().size() == 1 ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_NE(WEXITSTATUS(status), 10) << "sched_setaffinity failed in the child";
    EXPECT_EQ(WEXITSTATUS(status), 0) << "bound to one core, the default pool is not one thread";
}

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
