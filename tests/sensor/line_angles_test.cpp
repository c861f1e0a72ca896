// A line scanner's angles and times in AVX2 lanes: the same bits as one pulse at a time, for
// both waveforms, odd counts (tails) and pulse indices far from 0.
#include "sensor/detail/line_angles.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <vector>

namespace beamtrace::detail {
namespace {

void expect_same_bits(const LineAngleParams& p, std::uint64_t first, std::size_t count) {
    std::vector<double> lane_angle(count, -1.0), lane_time(count, -1.0);
    std::vector<double> angle(count), time(count);
    const std::size_t done =
        line_angles_lanes(p, first, count, lane_angle.data(), lane_time.data());
    if (__builtin_cpu_supports("avx2")) {
        EXPECT_EQ(done, count / 4 * 4);
    }
    line_angles_scalar(p, first + done, count - done, lane_angle.data() + done,
                       lane_time.data() + done);
    line_angles_scalar(p, first, count, angle.data(), time.data());
    for (std::size_t j = 0; j < count; ++j) {
        ASSERT_EQ(std::bit_cast<std::uint64_t>(lane_angle[j]),
                  std::bit_cast<std::uint64_t>(angle[j]))
            << "pulse " << first + j << " of " << count;
        ASSERT_EQ(std::bit_cast<std::uint64_t>(lane_time[j]), std::bit_cast<std::uint64_t>(time[j]))
            << "pulse " << first + j << " of " << count;
    }
}

TEST(LineAngles, LanesMatchOnePulseAtATime) {
    for (const bool triangle : {false, true}) {
        // 200 kHz, 100 lines/s (airborne_srtm), and rates whose quotients round.
        for (const LineAngleParams& p : {LineAngleParams{0.0, 200'000.0, 100.0, 30.0, triangle},
                                         LineAngleParams{1.5e5, 333'333.0, 137.0, 17.3, triangle},
                                         LineAngleParams{-2.25, 99'999.0, 71.0, 45.0, triangle}}) {
            for (const std::uint64_t first : {std::uint64_t{0}, std::uint64_t{1},
                                              std::uint64_t{4097}, std::uint64_t{123'456'789}}) {
                for (const std::size_t count : {1u, 3u, 4u, 5u, 7u, 256u, 1021u, 4003u}) {
                    expect_same_bits(p, first, count);
                }
            }
        }
    }
}

TEST(LineAngles, AnglesAreTheWaveform) {
    // 4 pulses a line: the sawtooth climbs -max, -max/2, 0, max/2; the triangle (2 lines a
    // period) reaches its peaks at whole lines.
    const LineAngleParams saw{0.0, 400.0, 100.0, 20.0, false};
    std::vector<double> angle(8), time(8);
    ASSERT_EQ(line_angles_lanes(saw, 0, 8, angle.data(), time.data()),
              __builtin_cpu_supports("avx2") ? 8u : 0u);
    line_angles_scalar(saw, 0, angle.size(), angle.data(), time.data());
    const std::vector<double> expect{-20.0, -10.0, 0.0, 10.0, -20.0, -10.0, 0.0, 10.0};
    EXPECT_EQ(angle, expect);
    EXPECT_DOUBLE_EQ(time[5], 5.0 / 400.0);
    std::vector<double> lane(8), lane_time(8);
    if (line_angles_lanes(saw, 0, 8, lane.data(), lane_time.data()) == 8) {
        EXPECT_EQ(lane, expect);
        EXPECT_EQ(lane_time, time);
    }
    const LineAngleParams tri{0.0, 400.0, 100.0, 20.0, true};
    line_angles_scalar(tri, 0, angle.size(), angle.data(), time.data());
    EXPECT_EQ(angle, (std::vector<double>{-20.0, -10.0, 0.0, 10.0, 20.0, 10.0, 0.0, -10.0}));
    if (line_angles_lanes(tri, 0, 8, lane.data(), lane_time.data()) == 8) {
        EXPECT_EQ(lane, angle);
    }
}

}  // namespace
}  // namespace beamtrace::detail
