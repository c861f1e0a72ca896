#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "physics/detail/gaussian_runs.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

using detail::GaussianRun;

/// One run after the other, each by its recurrence, added to y (bins from `first`).
void add_one_by_one(std::vector<double>& y, std::int64_t first, const std::vector<GaussianRun>& r) {
    for (const GaussianRun& run : r) {
        double g = run.g, ratio = run.ratio;
        for (std::size_t k = 0; k < run.n; ++k) {
            y[static_cast<std::size_t>(run.b0 - first) + k] += g;
            g *= ratio;
            ratio *= run.step;
        }
    }
}

TEST(GaussianRunLanes, BitForBitOneRunAfterTheOther) {
    if (!detail::run_lanes_available()) {
        BEAMTRACE_SKIP_HARDWARE("no AVX-512F on this CPU");
    }
    std::uint64_t s = 99;
    const auto next = [&s] {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(s >> 11) * 0x1p-53;
    };
    for (int trial = 0; trial < 2000; ++trial) {
        const std::int64_t first = 2000 + trial % 37;
        const std::size_t width = 1 + static_cast<std::size_t>(next() * 70.0);
        std::vector<double> want(width, 0.0), got(width, 0.0);
        // Chunks of up to 8 runs, as build_waveform adds them, some empty.
        for (int chunk = 0; chunk < 3; ++chunk) {
            std::vector<GaussianRun> runs(1 + static_cast<std::size_t>(next() * 8.0));
            for (GaussianRun& r : runs) {
                const auto at = static_cast<std::size_t>(next() * static_cast<double>(width));
                r.b0 = first + static_cast<std::int64_t>(at);
                r.n = next() < 0.1 ? 0 : static_cast<std::size_t>(next() * double(width - at + 1));
                r.g = 1e-7 * next();
                r.ratio = 1.0 + 0.5 * next();
                r.step = 0.9 + 0.09 * next();
            }
            add_one_by_one(want, first, runs);
            detail::add_runs_lanes(got.data(), width, first, runs.data(), runs.size());
        }
        for (std::size_t b = 0; b < width; ++b) {
            ASSERT_EQ(std::bit_cast<std::uint64_t>(got[b]), std::bit_cast<std::uint64_t>(want[b]))
                << "trial " << trial << " bin " << b;
        }
    }
}

TEST(GaussianRunLanes, LeavesBinsOutsideTheRunsAsTheyAre) {
    if (!detail::run_lanes_available()) {
        BEAMTRACE_SKIP_HARDWARE("no AVX-512F on this CPU");
    }
    std::vector<double> y(40, 0.25);
    const GaussianRun run{2.0, 0.5, 1.0, 110, 3};  // bins 110, 111, 112: 2, 1, 0.5
    detail::add_runs_lanes(y.data(), y.size(), 100, &run, 1);
    for (std::size_t b = 0; b < y.size(); ++b) {
        const double want = b == 10 ? 2.25 : b == 11 ? 1.25 : b == 12 ? 0.75 : 0.25;
        EXPECT_EQ(y[b], want) << b;
    }
}

}  // namespace
}  // namespace beamtrace
