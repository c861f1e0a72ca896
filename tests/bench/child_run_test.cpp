// Work in a forked child: its result and peak RSS come back, its errors are rethrown here.
#include "harness/child_run.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/memory_usage.hpp"

namespace beamtrace {
namespace {

TEST(ChildRun, ResultAndPeakRssAreTheChilds) {
    const std::size_t before = peak_rss_bytes();
    constexpr std::size_t kBytes = 300u << 20;
    const detail::ChildRun run = detail::run_in_child([] {
        std::vector<char> big(kBytes);
        std::memset(big.data(), 1, big.size());  // touched: resident
        return std::string("done ") + std::to_string(static_cast<int>(big[kBytes / 2]));
    });
    EXPECT_EQ(run.payload, "done 1");
    EXPECT_GE(run.peak_rss_bytes, kBytes);
    // The parent never held the child's 300 MB.
    EXPECT_LT(peak_rss_bytes(), before + kBytes / 2);
}

TEST(ChildRun, ErrorsComeBackWithTheirMessages) {
    try {
        (void)detail::run_in_child([]() -> std::string { throw InputError("a.las", "broken"); });
        FAIL() << "expected an Error";
    } catch (const ConfigError& e) {
        EXPECT_STREQ(e.what(), "a.las: broken");
    }
    try {
        (void)detail::run_in_child([]() -> std::string { throw std::logic_error("oops"); });
        FAIL() << "expected a runtime_error";
    } catch (const Error&) {
        FAIL() << "not a beamtrace error";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "oops");
    }
    EXPECT_THROW((void)detail::run_in_child([]() -> std::string { throw std::bad_alloc(); }),
                 std::bad_alloc);
    try {
        (void)detail::run_in_child([]() -> std::string {
            std::raise(SIGTERM);
            return "unreachable";
        });
        FAIL() << "expected a runtime_error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("killed by signal 15"), std::string::npos) << e.what();
    }
}

TEST(ChildRun, ThisTestProcessIsNotSingleThreadedOnceAThreadRuns) {
    // The check reads /proc/self/status; with a second thread alive it must say no.
    std::atomic<bool> stop{false};
    std::thread t([&] {
        while (!stop) {
            std::this_thread::yield();
        }
    });
    EXPECT_FALSE(detail::process_is_single_threaded());
    stop = true;
    t.join();
}

}  // namespace
}  // namespace beamtrace
