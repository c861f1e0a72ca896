#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
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

/// Uniform draws in [0, 1) from a 64-bit LCG: the same sequence for a seed on every machine.
struct Draws {
    std::uint64_t s;
    double operator()() {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(s >> 11) * 0x1p-53;
    }
};

/// Every bin of `got` has the bits of `want`'s.
void expect_same_bits(const std::vector<double>& got, const std::vector<double>& want,
                      const std::string& where) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t b = 0; b < got.size(); ++b) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(got[b]), std::bit_cast<std::uint64_t>(want[b]))
            << where << " bin " << b;
    }
}

/// The paths of add_runs_lanes, AVX2 and AVX-512.
class GaussianRunLanes : public ::testing::TestWithParam<detail::RunLanes> {
  protected:
    void SetUp() override {
        if (!detail::run_lanes_available(GetParam())) {
            BEAMTRACE_SKIP_HARDWARE("this path does not run on this CPU");
        }
    }
};

TEST_P(GaussianRunLanes, BitForBitOneRunAfterTheOther) {
    Draws next{99};
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
            detail::add_runs_lanes(GetParam(), got.data(), width, first, runs.data(), runs.size());
        }
        ASSERT_NO_FATAL_FAILURE(expect_same_bits(got, want, "trial " + std::to_string(trial)));
    }
}

// Up to kRunsPerCall runs in one call (AVX2: up to twenty a pass over the bins, in fours), as a
// many-ray pulse's waveform receives them: most sharing most of their bins (the blocks every run
// reaches go without masks), some without bins but with samples that would show, some apart.
TEST_P(GaussianRunLanes, ManyRunsInOneCallBitForBit) {
    Draws next{7};
    for (int trial = 0; trial < 3000; ++trial) {
        const std::int64_t first = 500 + trial % 13;
        const std::size_t width = 8 + static_cast<std::size_t>(next() * 90.0);
        const std::size_t count = 1 + static_cast<std::size_t>(trial) % detail::kRunsPerCall;
        const bool apart = trial % 5 == 0;
        std::vector<GaussianRun> runs(count);
        for (GaussianRun& r : runs) {
            const auto at = static_cast<std::size_t>(next() * (apart ? double(width) : 6.0));
            const std::size_t room = width - at;
            r.b0 = first + static_cast<std::int64_t>(at);
            r.n = apart ? static_cast<std::size_t>(next() * double(room + 1))
                        : room - std::min(room, static_cast<std::size_t>(next() * 6.0));
            r.n = next() < 0.05 ? 0 : r.n;
            r.g = 1e-7 * (0.5 + next());
            r.ratio = 1.0 + 0.5 * next();
            r.step = 0.9 + 0.09 * next();
        }
        std::vector<double> want(width), got(width);
        for (std::size_t b = 0; b < width; ++b) {
            want[b] = got[b] = 1e-8 * next();
        }
        add_one_by_one(want, first, runs);
        detail::add_runs_lanes(GetParam(), got.data(), width, first, runs.data(), runs.size());
        ASSERT_NO_FATAL_FAILURE(expect_same_bits(
            got, want, "trial " + std::to_string(trial) + " count " + std::to_string(count)));
    }
}

TEST_P(GaussianRunLanes, LeavesBinsOutsideTheRunsAsTheyAre) {
    std::vector<double> y(40, 0.25);
    const GaussianRun run{2.0, 0.5, 1.0, 110, 3};  // bins 110, 111, 112: 2, 1, 0.5
    detail::add_runs_lanes(GetParam(), y.data(), y.size(), 100, &run, 1);
    for (std::size_t b = 0; b < y.size(); ++b) {
        const double want = b == 10 ? 2.25 : b == 11 ? 1.25 : b == 12 ? 0.75 : 0.25;
        EXPECT_EQ(y[b], want) << b;
    }
}

// Eight runs, each of its own bins, over a width not a multiple of four: the last block's bins
// beyond the width are neither read nor written, and each run lands in its own bins only.
TEST_P(GaussianRunLanes, EightRunsEachInItsOwnBins) {
    std::vector<double> y(27, 0.0);
    y.push_back(-0.0);  // a guard past the width (-0 + +0 would make it +0)
    std::vector<GaussianRun> runs(8);
    for (std::size_t l = 0; l < runs.size(); ++l) {
        runs[l] = GaussianRun{static_cast<double>(l + 1), 1.0, 1.0, 50 + 3 * std::int64_t(l), 3};
    }
    runs[7].n = 6;  // bins 71..76: up to the last bin (index 26)
    detail::add_runs_lanes(GetParam(), y.data(), 27, 50, runs.data(), runs.size());
    for (std::size_t b = 0; b < 27; ++b) {
        EXPECT_EQ(y[b], static_cast<double>(std::min<std::size_t>(b / 3, 7) + 1)) << b;
    }
    EXPECT_EQ(std::bit_cast<std::uint64_t>(y[27]), std::bit_cast<std::uint64_t>(-0.0));
}

std::string path_name(const ::testing::TestParamInfo<detail::RunLanes>& info) {
    return info.param == detail::RunLanes::avx2 ? "Avx2" : "Avx512";
}

INSTANTIATE_TEST_SUITE_P(Paths, GaussianRunLanes,
                         ::testing::Values(detail::RunLanes::avx2, detail::RunLanes::avx512),
                         path_name);

}  // namespace
}  // namespace beamtrace
