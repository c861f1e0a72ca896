#include "beamtrace/core/memory_usage.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>

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

}  // namespace
}  // namespace beamtrace
