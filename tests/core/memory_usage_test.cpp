#include "beamtrace/core/memory_usage.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

#include "heightfield/child_peak_rss.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

TEST(MemoryUsage, PeakFollowsATouchedAllocationAndResets) {
    const std::size_t before = current_rss_bytes();
    ASSERT_GT(before, 0u) << "no /proc/self/status";
    constexpr std::size_t kBytes = std::size_t{256} << 20;
    {
        const auto block = std::make_unique<char[]>(kBytes);
        std::memset(block.get(), 1, kBytes);  // touched: resident
        EXPECT_GE(current_rss_bytes(), before + kBytes * 9 / 10);
    }
    EXPECT_GE(peak_rss_bytes(), before + kBytes * 9 / 10);
#ifndef BEAMTRACE_SANITIZED  // AddressSanitizer keeps freed blocks in quarantine
    if (reset_peak_rss()) {
        // Freed (glibc returns a block this large to the system), so the new peak is near now.
        EXPECT_LT(peak_rss_bytes(), before + kBytes / 2);
    }
#endif
}

#ifndef BEAMTRACE_SANITIZED  // the shadow memory of AddressSanitizer would be counted here too
TEST(MemoryUsage, ChildPeakRssIsTheChildsOwnNotThisProcesssCopy) {
    // dd holds one block of bs bytes, written by each read: a child whose peak is known.
    const std::filesystem::path dd = std::filesystem::exists("/bin/dd") ? "/bin/dd" : "/usr/bin/dd";
    if (!std::filesystem::exists(dd)) {
        BEAMTRACE_SKIP_OR_FAIL("no dd (coreutils)");
    }
    const test::TempDir dir;
    // This process holds 256 MB while the children run: with fork + exec, ru_maxrss would
    // report at least that for both.
    constexpr std::size_t kHeld = std::size_t{256} << 20;
    const auto held = std::make_unique<char[]>(kHeld);
    std::memset(held.get(), 1, kHeld);
    const auto run = [&](const char* block) {
        const test::ChildPeak peak = test::run_measuring_peak_rss(
            {dd.string(), "if=/dev/zero", "of=/dev/null", std::string("bs=") + block, "count=2"},
            dir / "dd.log");
        EXPECT_EQ(peak.exit_code, 0) << test::read_file(dir / "dd.log");
        EXPECT_TRUE(peak.error.empty()) << peak.error;
        return peak.peak_rss_bytes;
    };
    const std::size_t small = run("1M");
    const std::size_t large = run("100M");
    EXPECT_GT(small, 0u);
    EXPECT_LT(small, std::size_t{16} << 20) << "the child's peak includes this process's memory";
    EXPECT_GE(large, small + (std::size_t{100} << 20) * 9 / 10);
    EXPECT_LT(large, (std::size_t{100} << 20) + (std::size_t{16} << 20));
    std::printf("[ rss      ] dd bs=1M: %.1f MB, bs=100M: %.1f MB (this process holds %.0f MB)\n",
                static_cast<double>(small) / 1e6, static_cast<double>(large) / 1e6,
                static_cast<double>(current_rss_bytes()) / 1e6);
}
#endif

}  // namespace
}  // namespace beamtrace
