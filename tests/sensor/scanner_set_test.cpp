// ScannerSet: several scanners' pulses merged by GPS time, then scanner index.
#include "beamtrace/sensor/scanner_set.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/leg_sequence.hpp"
#include "beamtrace/sensor/line_scanner.hpp"
#include "beamtrace/sensor/rotating_presets.hpp"
#include "beamtrace/sensor/rotating_scanner.hpp"
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

std::vector<std::unique_ptr<ScanPattern>> patterns(std::unique_ptr<ScanPattern> a,
                                                   std::unique_ptr<ScanPattern> b,
                                                   std::unique_ptr<ScanPattern> c = nullptr) {
    std::vector<std::unique_ptr<ScanPattern>> v;
    v.push_back(std::move(a));
    v.push_back(std::move(b));
    if (c) {
        v.push_back(std::move(c));
    }
    return v;
}

/// Brute force: every scanner's pulses, (time, scanner, own index), sorted.
std::vector<std::tuple<double, std::size_t, std::size_t>> brute_order(const ScannerSet& set) {
    std::vector<std::tuple<double, std::size_t, std::size_t>> all;
    for (std::size_t s = 0; s < set.scanner_count(); ++s) {
        const PulseBatch own = test::all_pulses(set.scanner(s));
        for (std::size_t i = 0; i < own.size(); ++i) {
            all.emplace_back(own.time_s[i], s, i);
        }
    }
    std::sort(all.begin(), all.end());
    return all;
}

/// The set's pulses are its scanners' own, bit for bit, in the brute-force order; the
/// scanner index of each is right, pulse_time_s agrees, and chunking changes nothing.
void expect_merged_like_brute_force(const ScannerSet& set) {
    const auto order = brute_order(set);
    ASSERT_EQ(set.pulse_count(), order.size());
    std::vector<PulseBatch> own;
    for (std::size_t s = 0; s < set.scanner_count(); ++s) {
        own.push_back(test::all_pulses(set.scanner(s)));
    }
    const PulseBatch all = test::all_pulses(set);
    for (std::size_t k = 0; k < all.size(); ++k) {
        const auto [t, s, i] = order[k];
        ASSERT_EQ(all.scanner[k], s) << k;
        ASSERT_EQ(all.time_s[k], own[s].time_s[i]) << k;
        ASSERT_EQ(all.direction[k], own[s].direction[i]) << k;
        ASSERT_EQ(all.channel[k], own[s].channel[i]) << k;
        ASSERT_EQ(all.scan_angle_deg[k], own[s].scan_angle_deg[i]) << k;
        ASSERT_EQ(set.pulse_time_s(k), all.time_s[k]) << k;
    }
    EXPECT_EQ(set.pulse_time_s(set.pulse_count()), set.end_time_s());
    test::expect_chunking_does_not_matter(set, {1, 7, 100, 1024});
    // Chunks by hand for the scanner index too.
    PulseBatch part;
    for (std::uint64_t first = 0; first < set.pulse_count(); first += 37) {
        const auto n =
            static_cast<std::size_t>(std::min<std::uint64_t>(37, set.pulse_count() - first));
        set.generate(first, n, part);
        for (std::size_t j = 0; j < n; ++j) {
            ASSERT_EQ(part.scanner[j], all.scanner[first + j]) << first + j;
        }
    }
}

TEST(ScannerSet, MergesTwoRatesByTimeThenScannerIndex) {
    // 1 kHz from 0 and 1.5 kHz from 0: they fire together every 2 ms (scanner 0 first), and
    // 0.25 s of each gives 250 + 375 pulses.
    const ScannerSet set(patterns(line(1000, 0.0, 0.25, 20), line(1500, 0.0, 0.25, 10)));
    EXPECT_EQ(set.pulse_count(), 625u);
    EXPECT_EQ(set.scanner_count(), 2u);
    EXPECT_DOUBLE_EQ(set.start_time_s(), 0.0);
    EXPECT_DOUBLE_EQ(set.end_time_s(), 0.25);
    EXPECT_DOUBLE_EQ(set.pulse_rate_hz(), 2500.0);
    expect_merged_like_brute_force(set);
    const PulseBatch all = test::all_pulses(set);
    // t = 0: scanner 0, then 1; t = 1/1500: 1; t = 1/1000: 0; t = 2/1500: 1; t = 2/1000: 0, 1.
    const std::vector<std::uint8_t> first{0, 1, 1, 0, 1, 0, 1};
    EXPECT_EQ(std::vector<std::uint8_t>(all.scanner.begin(), all.scanner.begin() + 7), first);
    // The split after g pulses: how many of each scanner.
    EXPECT_EQ(set.split(0), (std::vector<std::uint64_t>{0, 0}));
    EXPECT_EQ(set.split(5), (std::vector<std::uint64_t>{2, 3}));
    EXPECT_EQ(set.split(625), (std::vector<std::uint64_t>{250, 375}));
}

TEST(ScannerSet, EqualScannersInterleaveAndOffsetStartsAndLegsMerge) {
    {
        const ScannerSet set(patterns(line(1000, 0.0, 0.1, 20), line(1000, 0.0, 0.1, 20)));
        const PulseBatch all = test::all_pulses(set);
        ASSERT_EQ(all.size(), 200u);
        for (std::size_t k = 0; k < all.size(); ++k) {
            ASSERT_EQ(all.scanner[k], k % 2) << k;
            ASSERT_EQ(all.time_s[k], static_cast<double>(k / 2) / 1000.0) << k;
        }
    }
    {
        // The second scanner starts later and ends later; a third is a LegSequence (a gap).
        std::vector<SequenceLeg> legs(3);
        legs[0] = {0.0, 0.05, line(2000, 0.0, 0.05, 5)};
        legs[1] = {0.05, 0.1, nullptr};
        legs[2] = {0.1, 0.2, line(700, 0.1, 0.1, 5)};
        const ScannerSet set(patterns(line(1000, 0.02, 0.1, 20), line(1300, 0.07, 0.2, 10),
                                      std::make_unique<LegSequence>(std::move(legs))));
        EXPECT_EQ(set.pulse_count(), 100u + 260u + 100u + 70u);
        EXPECT_DOUBLE_EQ(set.start_time_s(), 0.0);
        EXPECT_NEAR(set.end_time_s(), 0.27, 1e-12);
        expect_merged_like_brute_force(set);
    }
}

TEST(ScannerSet, RotatingHeadsWithTimingTablesMergeByTheirTrueFiringTimes) {
    // The VLP-16's lasers fire 2.304 us apart within each 55.296 us firing: not at
    // start + i / rate. Two heads, the second starting 1 us later, and a line scanner.
    RotatingScannerConfig a = velodyne_vlp16();
    a.duration_s = 0.002;
    RotatingScannerConfig b = a;
    b.start_time_s = 1e-6;
    const ScannerSet set(patterns(std::make_unique<RotatingScanner>(a),
                                  std::make_unique<RotatingScanner>(b),
                                  line(100000, 0.0, 0.002, 20)));
    const PulseBatch own = test::all_pulses(set.scanner(0));
    ASSERT_GT(own.size(), 32u);
    EXPECT_NEAR(own.time_s[1] - own.time_s[0], 2.304e-6, 1e-15);
    for (std::size_t i = 0; i < own.size(); ++i) {
        ASSERT_EQ(set.scanner(0).pulse_time_s(i), own.time_s[i]) << i;
    }
    expect_merged_like_brute_force(set);
}

TEST(ScannerSet, RefusesNoScannerOrANullOne) {
    EXPECT_THROW(ScannerSet(std::vector<std::unique_ptr<ScanPattern>>{}), ConfigError);
    EXPECT_THROW(ScannerSet(patterns(line(1000, 0.0, 0.1, 20), nullptr)), ConfigError);
}

}  // namespace
}  // namespace beamtrace
