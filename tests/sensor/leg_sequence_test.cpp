// LegSequence: legs with their own scanners (rates, angles) and legs with the scanner off.
#include "beamtrace/sensor/leg_sequence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/line_scanner.hpp"
#include "scan_pattern_test_support.hpp"

namespace beamtrace {
namespace {

std::unique_ptr<ScanPattern> line(double rate_hz, double start_s, double duration_s,
                                  double max_deg) {
    LineScannerConfig c;
    c.pulse_rate_hz = rate_hz;
    c.scan_rate_hz = 10;
    c.scan_angle_max_deg = max_deg;
    c.start_time_s = start_s;
    c.duration_s = duration_s;
    return std::make_unique<LineScanner>(c);
}

/// Leg 0: 1 kHz over [0, 1); leg 1: off over [1, 2); leg 2: 3 kHz over [2, 2.5), 10 degrees.
LegSequence three_legs() {
    std::vector<SequenceLeg> legs(3);
    legs[0] = {0.0, 1.0, line(1000, 0.0, 1.0, 20)};
    legs[1] = {1.0, 2.0, nullptr};
    legs[2] = {2.0, 2.5, line(3000, 2.0, 0.5, 10)};
    return LegSequence(std::move(legs));
}

TEST(LegSequence, EachLegFiresItsOwnPulsesInItsWindowAndNoneWhenOff) {
    const LegSequence seq = three_legs();
    ASSERT_EQ(seq.pulse_count(), 1000u + 1500u);
    EXPECT_EQ(seq.first_pulse(0), 0u);
    EXPECT_EQ(seq.first_pulse(1), 1000u);
    EXPECT_EQ(seq.first_pulse(2), 1000u);
    EXPECT_EQ(seq.first_pulse(3), 2500u);
    EXPECT_DOUBLE_EQ(seq.start_time_s(), 0.0);
    EXPECT_DOUBLE_EQ(seq.end_time_s(), 2.5);
    EXPECT_DOUBLE_EQ(seq.pulse_rate_hz(), 2500.0 / 2.5);
    const PulseBatch all = test::all_pulses(seq);
    const PulseBatch leg0 = test::all_pulses(*line(1000, 0.0, 1.0, 20));
    const PulseBatch leg2 = test::all_pulses(*line(3000, 2.0, 0.5, 10));
    for (std::size_t i = 0; i < all.size(); ++i) {
        const bool first = i < 1000;
        const PulseBatch& own = first ? leg0 : leg2;
        const std::size_t j = first ? i : i - 1000;
        const double want_t =
            first ? static_cast<double>(i) / 1000.0 : 2.0 + static_cast<double>(j) / 3000.0;
        ASSERT_NEAR(all.time_s[i], want_t, 1e-12) << i;
        ASSERT_FALSE(all.time_s[i] >= 1.0 && all.time_s[i] < 2.0) << "pulse in the off leg";
        ASSERT_EQ(all.time_s[i], own.time_s[j]) << i;
        ASSERT_EQ(all.direction[i], own.direction[j]) << i;
        ASSERT_EQ(all.scan_angle_deg[i], own.scan_angle_deg[j]) << i;
        ASSERT_EQ(seq.pulse_time_s(i), all.time_s[i]) << i;
        ASSERT_EQ(seq.leg_of(i), first ? 0u : 2u) << i;
        ASSERT_LE(std::abs(all.scan_angle_deg[i]), first ? 20.0f : 10.0f) << i;
    }
    EXPECT_EQ(seq.pulse_time_s(seq.pulse_count()), seq.end_time_s());
}

TEST(LegSequence, ChunksAcrossLegsGiveTheSamePulses) {
    const LegSequence seq = three_legs();
    test::expect_chunking_does_not_matter(seq, {1, 7, 999, 1001, 4096});
}

TEST(LegSequence, AllLegsOffFireNothing) {
    std::vector<SequenceLeg> legs(2);
    legs[0] = {0.0, 1.0, nullptr};
    legs[1] = {1.0, 3.0, nullptr};
    const LegSequence seq(std::move(legs));
    EXPECT_EQ(seq.pulse_count(), 0u);
    EXPECT_EQ(seq.pulse_rate_hz(), 0.0);
}

TEST(LegSequence, OverlappingWindowsAndPatternsOutsideTheirLegAreRefused) {
    std::vector<SequenceLeg> overlap(2);
    overlap[0] = {0.0, 1.0, line(1000, 0.0, 1.0, 20)};
    overlap[1] = {0.5, 2.0, nullptr};
    EXPECT_THROW(LegSequence(std::move(overlap)), ConfigError);
    std::vector<SequenceLeg> outside(1);
    outside[0] = {0.0, 1.0, line(1000, 0.0, 1.5, 20)};
    EXPECT_THROW(LegSequence(std::move(outside)), ConfigError);
    EXPECT_THROW(LegSequence(std::vector<SequenceLeg>{}), ConfigError);
}

}  // namespace
}  // namespace beamtrace
