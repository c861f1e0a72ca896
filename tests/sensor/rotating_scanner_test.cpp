// Spinning multi-beam scanner: beam elevations, azimuth coverage per revolution, pulse timing,
// chunking independence, presets and validation.
#include "beamtrace/sensor/rotating_scanner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

PulseBatch all_pulses(const ScanPattern& pattern) {
    PulseBatch out;
    pattern.generate(0, static_cast<std::size_t>(pattern.pulse_count()), out);
    return out;
}

/// `deg` wrapped into [-180, 180).
double wrap(double deg) {
    double w = std::fmod(deg + 180.0, 360.0);
    return (w < 0.0 ? w + 360.0 : w) - 180.0;
}

/// Difference of two angles in degrees, in [-180, 180).
double angle_diff(double a, double b) {
    return wrap(a - b);
}

/// `n` elevations from `lo` to `hi` in equal steps, written out here rather than taken from the
/// library, so that a wrong preset table fails.
std::vector<double> steps(double lo, double hi, int n) {
    std::vector<double> v;
    for (int b = 0; b < n; ++b) {
        v.push_back(lo + (hi - lo) * b / (n - 1));
    }
    return v;
}

/// Every pulse's direction has unit length and the elevation configured for its channel, to
/// double rounding: sin, cos, atan2 and the degree conversion each round once, a few 1e-15
/// degrees at most, so 1e-13 degrees is ~30 ulps of 30 degrees and 1e-3 of a 0.1 degree error.
void expect_beam_elevations(const RotatingScannerConfig& config,
                            const std::vector<double>& elevations_deg) {
    const RotatingScanner scanner(config);
    const PulseBatch p = all_pulses(scanner);
    const std::size_t beams = elevations_deg.size();
    ASSERT_EQ(config.beam_elevations_deg.size(), beams);
    ASSERT_EQ(p.size() % beams, 0u);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3d d = p.direction[i];
        ASSERT_EQ(p.channel[i], i % beams);
        ASSERT_NEAR(length(d), 1.0, 1e-15);
        const double elevation = std::atan2(d.z, std::hypot(d.x, d.y)) * kRadToDeg;
        ASSERT_NEAR(elevation, elevations_deg[i % beams], 1e-13)
            << "pulse " << i << ", beam " << i % beams;
    }
}

TEST(RotatingScanner, DirectionsHaveExactlyTheBeamElevationsAndUnitLength) {
    // VLP-16 user manual, laser IDs 0-15 in firing order.
    expect_beam_elevations(vlp16(), {-15, 1, -13, 3, -11, 5, -9, 7, -7, 9, -5, 11, -3, 13, -1, 15});
    expect_beam_elevations(hdl32(), steps(-30.67, 10.67, 32));
    expect_beam_elevations(hdl64(), steps(-24.9, 2.0, 64));
    expect_beam_elevations(os128(), steps(-22.5, 22.5, 128));
    // Uneven beams up to the poles, with offsets and a clockwise spin.
    RotatingScannerConfig c;
    c.beam_elevations_deg = {-89.9, 0.1, -0.05, 33.3, 90.0 - 1e-6, -7.125};
    c.beam_azimuth_offsets_deg = {0, 1, -2, 3, -4, 5};
    c.spin_clockwise = true;
    c.azimuth_resolution_deg = 0.37;
    c.duration_s = 0.1;
    expect_beam_elevations(c, c.beam_elevations_deg);
}

TEST(RotatingScanner, OneRevolutionCoversTheCircleWithBeamsTimes360OverResolutionPulses) {
    RotatingScannerConfig c = vlp16();
    c.start_azimuth_deg = 30.0;
    const RotatingScanner scanner(c);
    const std::size_t beams = 16, firings = 1800;  // 360 / 0.2
    ASSERT_EQ(scanner.pulse_count(), beams * firings);
    const PulseBatch p = all_pulses(scanner);
    for (std::size_t b = 0; b < beams; ++b) {
        std::vector<double> az;
        for (std::size_t k = 0; k < firings; ++k) {
            const std::size_t i = k * beams + b;
            const Vec3d d = p.direction[i];
            const double a = std::atan2(d.y, d.x) * kRadToDeg;
            // Staggered beams: the head has turned b/16 of a step since the firing began.
            const double expected =
                30.0 + 0.2 * (static_cast<double>(k) + static_cast<double>(b) / 16.0);
            ASSERT_NEAR(angle_diff(a, expected), 0.0, 1e-9) << "beam " << b << " firing " << k;
            ASSERT_NEAR(angle_diff(p.scan_angle_deg[i], expected), 0.0, 1e-4);
            az.push_back(wrap(a));
        }
        // 1800 distinct azimuths, 0.2 degrees apart all the way round.
        std::sort(az.begin(), az.end());
        for (std::size_t k = 1; k < az.size(); ++k) {
            ASSERT_NEAR(az[k] - az[k - 1], 0.2, 1e-9);
        }
        EXPECT_NEAR(az.back() - az.front(), 360.0 - 0.2, 1e-9);
    }
}

/// The scan angle is the head's azimuth wrapped into [-180, 180) exactly as std::fmod wraps it,
/// float for float, whether the azimuth lies past 180 degrees (the sum 180 + azimuth in [360,
/// 720), which the scanner wraps by a subtraction), within [-180, 180) or far outside.
TEST(RotatingScanner, ScanAnglesAreTheAzimuthWrappedAsFmodWrapsIt) {
    for (const double start_deg : {170.0, -10.0, -900.5, 1000.25}) {
        RotatingScannerConfig c = vlp16();
        c.start_azimuth_deg = start_deg;
        const RotatingScanner scanner(c);
        const PulseBatch p = all_pulses(scanner);
        const std::size_t beams = 16;
        const double step = c.azimuth_step_deg();
        for (std::size_t i = 0; i < p.size(); ++i) {
            const std::size_t k = i / beams, b = i % beams;
            const double within = step * static_cast<double>(b) / static_cast<double>(beams);
            const double az = start_deg + 1.0 * (static_cast<double>(k) * step + within) + 0.0;
            ASSERT_EQ(p.scan_angle_deg[i], static_cast<float>(wrap(az)))
                << "start " << start_deg << " pulse " << i << " azimuth " << az;
        }
    }
}

TEST(RotatingScanner, TimesComeFromThePulseRate) {
    RotatingScannerConfig c = vlp16();
    c.start_time_s = 1000.5;
    c.duration_s = 0.25;  // 2.5 revolutions
    const RotatingScanner scanner(c);
    EXPECT_DOUBLE_EQ(scanner.pulse_rate_hz(), 16.0 * 18000.0);
    EXPECT_EQ(scanner.pulse_count(), 16u * 4500u);
    const PulseBatch p = all_pulses(scanner);
    for (std::size_t i = 0; i < p.size(); ++i) {
        ASSERT_EQ(p.time_s[i], 1000.5 + static_cast<double>(i) / 288000.0);
    }
    EXPECT_NEAR(scanner.end_time_s(), 1000.75, 1e-12);
}

TEST(RotatingScanner, RevolutionsRepeatExactly) {
    RotatingScannerConfig c = os128();
    c.duration_s = 0.3;
    const RotatingScanner scanner(c);
    const PulseBatch p = all_pulses(scanner);
    const std::size_t per_rev = 128 * 1024;
    ASSERT_EQ(p.size(), 3 * per_rev);
    for (std::size_t i = 0; i + per_rev < p.size(); i += 97) {
        ASSERT_EQ(p.direction[i], p.direction[i + per_rev]);
        ASSERT_NEAR(p.time_s[i + per_rev] - p.time_s[i], 0.1, 1e-12);
    }
}

/// Every pulse of `scanner` generated in chunks of `chunk` equals the same pulse of `whole`.
void expect_chunks_equal(const RotatingScanner& scanner, const PulseBatch& whole,
                         std::size_t chunk) {
    PulseBatch part;
    for (std::uint64_t first = 0; first < scanner.pulse_count(); first += chunk) {
        const auto n =
            static_cast<std::size_t>(std::min<std::uint64_t>(chunk, scanner.pulse_count() - first));
        scanner.generate(first, n, part);
        ASSERT_EQ(part.size(), n);
        for (std::size_t j = 0; j < n; ++j) {
            const auto i = static_cast<std::size_t>(first + j);
            ASSERT_EQ(part.time_s[j], whole.time_s[i]) << "chunk " << chunk << " pulse " << i;
            ASSERT_EQ(part.direction[j], whole.direction[i]) << "chunk " << chunk << " pulse " << i;
            ASSERT_EQ(part.channel[j], whole.channel[i]) << "chunk " << chunk << " pulse " << i;
            ASSERT_EQ(part.scan_angle_deg[j], whole.scan_angle_deg[i])
                << "chunk " << chunk << " pulse " << i;
        }
    }
}

// Chunks of 1 and 3 pulses take the scalar path; longer ones run a firing's beams four at a time
// in lanes where the CPU has AVX2 (also from a beam that is not a multiple of 4, and with the
// scalar path for a four whose azimuths need fmod to wrap): the same bits either way.
TEST(RotatingScanner, AnyChunkingGivesIdenticalPulses) {
    RotatingScannerConfig c = hdl64();
    c.beam_azimuth_offsets_deg.assign(64, 0.0);
    for (std::size_t b = 0; b < 64; ++b) {
        c.beam_azimuth_offsets_deg[b] = b % 2 == 0 ? -1.5 : 2.25;
    }
    c.spin_clockwise = true;
    c.azimuth_resolution_deg = 0.37;  // not a divisor of 360
    c.start_azimuth_deg = -170.0;
    c.duration_s = 0.05;
    // Azimuths from 450 degrees on: the first firings' wrap by subtracting 360, those past 540
    // degrees by fmod.
    RotatingScannerConfig far = c;
    far.start_azimuth_deg = 450.0;
    far.spin_clockwise = false;
    far.beam_channels.resize(64);
    for (std::size_t b = 0; b < 64; ++b) {
        far.beam_channels[b] = static_cast<std::uint16_t>(100 + 3 * b);
    }
    for (const RotatingScannerConfig& config : {c, far}) {
        const RotatingScanner scanner(config);
        const PulseBatch whole = all_pulses(scanner);
        EXPECT_EQ(whole.channel[5], config.beam_channels.empty() ? 5 : 115);
        for (const std::size_t chunk : {std::size_t{1}, std::size_t{3}, std::size_t{7},
                                        std::size_t{64}, std::size_t{1000}, std::size_t{4099}}) {
            expect_chunks_equal(scanner, whole, chunk);
        }
    }
}

TEST(RotatingScanner, ClockwiseSpinAndBeamOffsets) {
    RotatingScannerConfig c;
    c.beam_elevations_deg = {0.0, 10.0};
    c.beam_azimuth_offsets_deg = {0.0, 5.0};
    c.rotation_rate_hz = 10.0;
    c.azimuth_resolution_deg = 1.0;
    c.spin_clockwise = true;
    c.duration_s = 0.1;
    const RotatingScanner scanner(c);
    ASSERT_EQ(scanner.pulse_count(), 720u);
    PulseBatch p;
    scanner.generate(0, 4, p);
    // Firing 0: beam 0 at azimuth 0, beam 1 half a step later (-0.5) plus its 5 degree offset.
    EXPECT_NEAR(p.scan_angle_deg[0], 0.0, 1e-6);
    EXPECT_NEAR(p.scan_angle_deg[1], 4.5, 1e-6);
    // Firing 1: the head has turned clockwise, towards -y.
    EXPECT_NEAR(p.scan_angle_deg[2], -1.0, 1e-6);
    EXPECT_LT(p.direction[2].y, 0.0);
    EXPECT_NEAR(p.direction[0].x, 1.0, 1e-15);
}

TEST(RotatingScanner, PresetsHaveTheirBeamsAndRates) {
    struct Expect {
        RotatingScannerConfig config;
        std::size_t beams;
        double lowest_deg, highest_deg, firings_per_rev;
    };
    for (const Expect& e :
         {Expect{vlp16(), 16, -15.0, 15.0, 1800.0}, Expect{hdl32(), 32, -30.67, 10.67, 2250.0},
          Expect{hdl64(), 64, -24.9, 2.0, 2000.0}, Expect{os128(), 128, -22.5, 22.5, 1024.0}}) {
        EXPECT_TRUE(e.config.validate().empty());
        ASSERT_EQ(e.config.beam_elevations_deg.size(), e.beams);
        std::vector<double> sorted = e.config.beam_elevations_deg;
        std::sort(sorted.begin(), sorted.end());
        EXPECT_NEAR(sorted.front(), e.lowest_deg, 1e-12);
        EXPECT_NEAR(sorted.back(), e.highest_deg, 1e-12);
        const double step = (e.highest_deg - e.lowest_deg) / static_cast<double>(e.beams - 1);
        for (std::size_t b = 1; b < sorted.size(); ++b) {
            EXPECT_NEAR(sorted[b] - sorted[b - 1], step, 1e-9);
        }
        EXPECT_NEAR(360.0 / e.config.azimuth_resolution_deg, e.firings_per_rev, 1e-9);
        EXPECT_EQ(RotatingScanner(e.config).pulse_count(),
                  static_cast<std::uint64_t>(static_cast<double>(e.beams) *
                                             e.firings_per_rev));  // 0.1 s = 1 rev
    }
    EXPECT_EQ(vlp16().beam_elevations_deg[1], 1.0);  // VLP-16 laser ID order
}

TEST(RotatingScanner, ValidationListsEveryProblem) {
    RotatingScannerConfig c;
    c.beam_elevations_deg = {0.0, 95.0};
    c.beam_azimuth_offsets_deg = {1.0};
    c.rotation_rate_hz = -1.0;
    c.azimuth_resolution_deg = 0.0;
    c.duration_s = 0.0;
    const auto problems = c.validate();
    EXPECT_EQ(problems.size(), 5u);
    try {
        RotatingScanner scanner(c);
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const char* key : {"beam_elevations_deg[1]", "beam_azimuth_offsets_deg",
                                "rotation_rate_hz", "azimuth_resolution_deg", "duration_s"}) {
            EXPECT_NE(msg.find(key), std::string::npos) << msg;
        }
    }
    RotatingScannerConfig empty;
    EXPECT_FALSE(empty.validate().empty());  // no beams
    RotatingScannerConfig too_short = vlp16();
    too_short.duration_s = 1e-6;  // shorter than one firing
    EXPECT_THROW(RotatingScanner{too_short}, ConfigError);
}

TEST(RotatingScanner, GeneratingPastTheEndThrows) {
    const RotatingScanner scanner(vlp16());
    PulseBatch p;
    EXPECT_THROW(scanner.generate(scanner.pulse_count() - 2, 3, p), std::out_of_range);
    EXPECT_NO_THROW(scanner.generate(scanner.pulse_count(), 0, p));
    EXPECT_TRUE(p.empty());
}

}  // namespace
}  // namespace beamtrace
