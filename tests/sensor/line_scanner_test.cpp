// Airborne line scanner: waveforms, timing, chunking, and an analytic flight over the plane
// z = 0 (swath width, line spacing, motion distortion).
#include "beamtrace/sensor/line_scanner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/trajectory.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegToRad = kPi / 180.0;

LineScannerConfig config(ScanWaveform waveform) {
    LineScannerConfig c;
    c.pulse_rate_hz = 100'000.0;
    // 100 lines/s, 1000 pulses per line: a sawtooth period is one line, an oscillating
    // mirror's (triangle, sinusoid) two.
    c.scan_rate_hz = waveform == ScanWaveform::sawtooth ? 100.0 : 50.0;
    c.scan_angle_max_deg = 20.0;
    c.waveform = waveform;
    c.duration_s = 0.05;  // 5 lines
    return c;
}

PulseBatch all_pulses(const ScanPattern& pattern) {
    PulseBatch out;
    pattern.generate(0, static_cast<std::size_t>(pattern.pulse_count()), out);
    return out;
}

/// The beam's angle from the sensor x axis towards +y, in degrees.
double beam_angle_deg(const Vec3d& d) {
    return std::atan2(d.y, d.x) / kDegToRad;
}

TEST(LineScanner, SawtoothRampsFromMinusToPlusMaxEveryLine) {
    const LineScanner scanner(config(ScanWaveform::sawtooth));
    ASSERT_EQ(scanner.pulse_count(), 5000u);
    const PulseBatch p = all_pulses(scanner);
    double lo = 1e9, hi = -1e9;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double j = static_cast<double>(i % 1000);
        const double expected = -20.0 + 40.0 * j / 1000.0;
        ASSERT_NEAR(beam_angle_deg(p.direction[i]), expected, 1e-9) << i;
        ASSERT_NEAR(p.scan_angle_deg[i], expected, 1e-5);
        ASSERT_EQ(p.direction[i].z, 0.0);
        ASSERT_NEAR(length(p.direction[i]), 1.0, 1e-15);
        ASSERT_EQ(p.channel[i], 0);
        ASSERT_EQ(scanner.line_of_pulse(i), i / 1000);
        lo = std::min(lo, beam_angle_deg(p.direction[i]));
        hi = std::max(hi, beam_angle_deg(p.direction[i]));
    }
    EXPECT_NEAR(lo, -20.0, 1e-12);              // reached at each line's start
    EXPECT_NEAR(hi, 20.0 - 40.0 / 1000, 1e-9);  // one step short of +max, then fly back
    EXPECT_NEAR(scanner.scan_angle_deg_at(0.01 - 1e-9), 20.0, 1e-4);
}

TEST(LineScanner, TriangleIsSymmetricAndLinear) {
    const LineScanner scanner(config(ScanWaveform::triangle));
    const PulseBatch p = all_pulses(scanner);
    auto angle = [&](std::size_t i) { return beam_angle_deg(p.direction[i]); };
    EXPECT_NEAR(angle(0), -20.0, 1e-12);
    EXPECT_NEAR(angle(1000), 20.0, 1e-12);  // turning point at the end of line 0
    EXPECT_NEAR(angle(2000), -20.0, 1e-12);
    for (std::size_t j = 1; j < 1000; ++j) {
        ASSERT_NEAR(angle(1000 - j), angle(1000 + j), 1e-9) << j;   // symmetric about +max
        ASSERT_NEAR(angle(2000 + j), angle(j), 1e-9);               // periodic over 2 lines
        ASSERT_NEAR(angle(j) - angle(j - 1), 40.0 / 1000.0, 1e-9);  // linear ramp up
        ASSERT_NEAR(angle(1000 + j) - angle(1000 + j - 1), -40.0 / 1000.0, 1e-9);  // and down
    }
}

TEST(LineScanner, SinusoidHasTheScanAmplitude) {
    const LineScanner scanner(config(ScanWaveform::sinusoid));
    const PulseBatch p = all_pulses(scanner);
    double max_abs = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < 4000; ++i) {  // two whole mirror periods
        const double a = beam_angle_deg(p.direction[i]);
        const double expected = -20.0 * std::cos(kPi * static_cast<double>(i) / 1000.0);
        ASSERT_NEAR(a, expected, 1e-9) << i;
        max_abs = std::max(max_abs, std::abs(a));
        sum += a;
    }
    EXPECT_NEAR(max_abs, 20.0, 1e-12);  // the half-angle is scan_angle_max
    EXPECT_NEAR(sum / 4000.0, 0.0, 1e-9);
}

TEST(LineScanner, TimesComeFromThePulseRateAndChunkingDoesNotMatter) {
    LineScannerConfig c = config(ScanWaveform::sinusoid);
    c.start_time_s = 86400.25;
    c.pulse_rate_hz = 33'333.0;  // not a multiple of the line rate
    c.scan_rate_hz = 71.0;
    c.duration_s = 0.3;
    const LineScanner scanner(c);
    EXPECT_EQ(scanner.pulse_count(), 9999u);
    const PulseBatch whole = all_pulses(scanner);
    for (std::size_t i = 0; i < whole.size(); ++i) {
        ASSERT_EQ(whole.time_s[i], 86400.25 + static_cast<double>(i) / 33'333.0);
    }
    for (const std::size_t chunk : {std::size_t{1}, std::size_t{13}, std::size_t{4096}}) {
        PulseBatch part;
        for (std::uint64_t first = 0; first < scanner.pulse_count(); first += chunk) {
            const auto n = static_cast<std::size_t>(
                std::min<std::uint64_t>(chunk, scanner.pulse_count() - first));
            scanner.generate(first, n, part);
            for (std::size_t j = 0; j < n; ++j) {
                const auto i = static_cast<std::size_t>(first + j);
                ASSERT_EQ(part.time_s[j], whole.time_s[i]);
                ASSERT_EQ(part.direction[j], whole.direction[i]);
                ASSERT_EQ(part.scan_angle_deg[j], whole.scan_angle_deg[i]);
            }
        }
    }
}

std::array<std::uint64_t, 3> bits_of(const Vec3d& v) {
    return {std::bit_cast<std::uint64_t>(v.x), std::bit_cast<std::uint64_t>(v.y),
            std::bit_cast<std::uint64_t>(v.z)};
}

/// Pulses of `scanner` from a batch reused in chunks (its sincos memo warm: lines repeat their
/// angles bit for bit) against each pulse alone from a fresh batch (the memo cold: every sin
/// and cos computed): the same bits.
void expect_memo_gives_what_sincos_gives(const LineScanner& scanner) {
    PulseBatch warm, cold;
    std::size_t checked = 0;
    for (std::uint64_t first = 0; first < scanner.pulse_count(); first += 1024) {
        const auto n =
            static_cast<std::size_t>(std::min<std::uint64_t>(1024, scanner.pulse_count() - first));
        scanner.generate(first, n, warm);
        for (std::size_t j = first % 3; j < n; j += 37) {  // a sample of each chunk's slots
            cold = PulseBatch{};
            scanner.generate(first + j, 1, cold);
            ASSERT_EQ(bits_of(warm.direction[j]), bits_of(cold.direction[0]))
                << "pulse " << first + j;
            ++checked;
        }
    }
    EXPECT_GT(checked, scanner.pulse_count() / 40);
    // Every entry holds an angle and its own cos and sin.
    ASSERT_FALSE(warm.sincos_memo.entries.empty());
    for (const SincosMemo::Entry& e : warm.sincos_memo.entries) {
        const double s = std::bit_cast<double>(e.angle_bits);
        ASSERT_EQ(std::bit_cast<std::uint64_t>(e.cos), std::bit_cast<std::uint64_t>(std::cos(s)));
        ASSERT_EQ(std::bit_cast<std::uint64_t>(e.sin), std::bit_cast<std::uint64_t>(std::sin(s)));
    }
}

TEST(LineScanner, DirectionsFromTheSincosMemoAreThoseOfSinAndCos) {
    // 200 lines (binades of the line count up to 128-255) of 1000 pulses, each waveform; and a
    // pulse rate with no whole number of pulses per line.
    for (const ScanWaveform waveform :
         {ScanWaveform::sawtooth, ScanWaveform::triangle, ScanWaveform::sinusoid}) {
        LineScannerConfig c = config(waveform);
        c.duration_s = 2.0;
        expect_memo_gives_what_sincos_gives(LineScanner(c));
        c.turn_duration_s = waveform == ScanWaveform::triangle ? 1e-3 : 0.0;
        c.pulse_rate_hz = 33'333.0;
        c.start_time_s = 1000.5;
        expect_memo_gives_what_sincos_gives(LineScanner(c));
    }
    // A batch reused by another scanner (a wider field of view): the memo's angles still hold.
    LineScannerConfig c = config(ScanWaveform::sawtooth);
    PulseBatch batch;
    LineScanner(c).generate(0, 2000, batch);
    c.scan_angle_max_deg = 35.0;
    const LineScanner wide(c);
    wide.generate(0, 2000, batch);
    PulseBatch fresh;
    wide.generate(0, 2000, fresh);
    for (std::size_t j = 0; j < 2000; ++j) {
        ASSERT_EQ(batch.direction[j], fresh.direction[j]) << j;
    }
}

/// A nadir line scanner flown along +x at height H and speed v over the plane z = 0.
struct Flight {
    static constexpr double kHeight = 500.0, kSpeed = 60.0;
    LinearLegs legs{{{{0.0, 0.0, kHeight}, {1000.0, 0.0, kHeight}}, {}, kSpeed, 0.0}};
    Mount mount = Mount::from_lever_arm({0.0, 0.0, 0.0}, {0.0, -kPi / 2, 0.0});

    /// Where pulse j of `p` meets the ground: t = H / -d_z along the world direction.
    [[nodiscard]] Vec3d ground(const PulseBatch& p, std::size_t j) const {
        const Pose pose = sensor_pose(legs, mount, p.time_s[j]);
        const Vec3d o = pose.apply_point({0.0, 0.0, 0.0});
        const Vec3d d = pose.apply_direction(p.direction[j]);
        EXPECT_LT(d.z, 0.0);
        return o + d * (o.z / -d.z);
    }
};

TEST(LineScanner, NadirFlightSwathIsTwoHTanMaxAndCrossTrackIsHTanScanAngle) {
    const Flight flight;
    const double h = Flight::kHeight;
    for (const ScanWaveform w : {ScanWaveform::triangle, ScanWaveform::sinusoid}) {
        const LineScanner scanner(config(w));
        const PulseBatch p = all_pulses(scanner);
        double y_min = 1e9, y_max = -1e9;
        for (std::size_t j = 0; j < p.size(); ++j) {
            const Vec3d g = flight.ground(p, j);
            const double s = beam_angle_deg(p.direction[j]) * kDegToRad;
            ASSERT_NEAR(g.z, 0.0, 1e-9);
            ASSERT_NEAR(g.y, h * std::tan(s), 1e-9) << "positive scan angle lands left (+y)";
            y_min = std::min(y_min, g.y);
            y_max = std::max(y_max, g.y);
        }
        const double swath = 2.0 * h * std::tan(20.0 * kDegToRad);
        EXPECT_NEAR(y_max - y_min, swath, 1e-9) << to_string(w);
        EXPECT_NEAR(y_max, -y_min, 1e-9);
    }
}

TEST(LineScanner, SawtoothLinesAreVOverScanRateApartWithMotionDistortion) {
    const Flight flight;
    const LineScanner scanner(config(ScanWaveform::sawtooth));
    const PulseBatch p = all_pulses(scanner);
    const double v = Flight::kSpeed, spacing = v / 100.0;
    for (std::size_t line = 0; line < 5; ++line) {
        const std::size_t first = line * 1000;
        const Vec3d start = flight.ground(p, first);
        EXPECT_NEAR(start.x, static_cast<double>(line) * spacing, 1e-9);  // lines v / rate apart
        EXPECT_NEAR(start.y, -Flight::kHeight * std::tan(20.0 * kDegToRad), 1e-9);
        const double line_start_s = scanner.line_start_time_s(line);
        EXPECT_NEAR(line_start_s, p.time_s[first], 1e-15);
        for (std::size_t j = first; j < first + 1000; ++j) {
            // Constant velocity: the along-track offset within a line is v (t - t_line).
            ASSERT_NEAR(flight.ground(p, j).x - start.x, v * (p.time_s[j] - line_start_s), 1e-9);
        }
    }
}

TEST(LineScanner, ScanRateIsTheMirrorFrequency) {
    // Data sheets and HELIOS++: 50 Hz is 50 mirror periods per second, 100 lines for an
    // oscillating mirror; a sawtooth period is one line.
    LineScannerConfig c = config(ScanWaveform::triangle);
    c.pulse_rate_hz = 70'000.0;
    c.scan_rate_hz = 50.0;
    EXPECT_EQ(c.lines_per_s(), 100.0);
    const LineScanner tri(c);
    EXPECT_EQ(tri.line_of_pulse(699), 0u);
    EXPECT_EQ(tri.line_of_pulse(700), 1u);  // 700 pulses per line
    EXPECT_EQ(tri.line_start_time_s(1), 0.01);
    EXPECT_NEAR(tri.scan_angle_deg_at(0.01), 20.0, 1e-9);   // +max at the end of line 0
    EXPECT_NEAR(tri.scan_angle_deg_at(0.02), -20.0, 1e-9);  // one mirror period
    c.waveform = ScanWaveform::sinusoid;
    EXPECT_NEAR(LineScanner(c).scan_angle_deg_at(0.02), -20.0, 1e-9);
    EXPECT_NEAR(LineScanner(c).scan_angle_deg_at(0.01), 20.0, 1e-9);
    c.waveform = ScanWaveform::sawtooth;
    EXPECT_EQ(c.lines_per_s(), 50.0);
    EXPECT_EQ(LineScanner(c).line_of_pulse(1400), 1u);
}

/// The angle of an oscillating mirror with turns of duration D, written out from the model
/// (docs/survey.md): line period T, half turn h = D/2, sweep speed w = 2 max / (T - h).
double turning_mirror_deg(double t, double max_deg, double line_s, double turn_s) {
    const double n = std::floor(t / line_s), u = t - n * line_s, h = turn_s / 2;
    const double w = 2 * max_deg / (line_s - h), acc = w / h;
    double s = 0;
    if (u < h) {
        s = -max_deg + acc * u * u / 2;
    } else if (u < line_s - h) {
        s = -max_deg + acc * h * h / 2 + w * (u - h);
    } else {
        s = max_deg - acc * (line_s - u) * (line_s - u) / 2;
    }
    return static_cast<long long>(n) % 2 == 0 ? s : -s;
}

TEST(LineScanner, MirrorTurnsAtFiniteAccelerationAtEachEnd) {
    LineScannerConfig c = config(ScanWaveform::triangle);  // 1000 pulses per line, +/-20 deg
    c.turn_duration_s = 1e-3;                              // 100 pulses turning at each end
    const LineScanner scanner(c);
    const PulseBatch p = all_pulses(scanner);
    const double w_per_pulse = 40.0 / (1000.0 - 50.0);  // the sweep's step, degrees
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double t = p.time_s[i];
        ASSERT_NEAR(beam_angle_deg(p.direction[i]), turning_mirror_deg(t, 20, 0.01, 1e-3), 1e-9)
            << i;
        ASSERT_LE(std::abs(beam_angle_deg(p.direction[i])), 20.0 + 1e-12) << i;
    }
    auto angle = [&](std::size_t i) { return beam_angle_deg(p.direction[i]); };
    EXPECT_NEAR(angle(1000), 20.0, 1e-9);  // the ends are still reached exactly
    EXPECT_NEAR(angle(2000), -20.0, 1e-9);
    for (std::size_t j = 51; j < 949; ++j) {  // constant speed between the turns
        ASSERT_NEAR(angle(j) - angle(j - 1), w_per_pulse, 1e-9) << j;
    }
    // In the turn the step shrinks linearly to 0 at the end and grows back: second differences
    // are the constant acceleration, w / 50 per pulse^2.
    for (std::size_t j = 955; j < 1045; ++j) {
        const double second = angle(j + 1) - 2 * angle(j) + angle(j - 1);
        if (j != 1000) {  // the end itself is where the direction flips
            ASSERT_NEAR(second, -w_per_pulse / 50.0, 1e-9) << j;
        }
    }
    // Pulses pile up at the ends: within the outer degree, v pulses before the end are
    // acc v^2 / 2 < 1 deg for v < sqrt(2 x 50 / w) = 48.7: 48 pulses of line 0, where an
    // instantaneous turn (0.04 deg per pulse) has 25.
    std::size_t near_end = 0;
    for (std::size_t i = 0; i < 1000; ++i) {
        near_end += angle(i) > 19.0 ? 1 : 0;
    }
    EXPECT_EQ(near_end, 48u);
}

TEST(LineScanner, LeicaAls50IIAsHeliosDefinesIt) {
    // HELIOS++ als_hd_demo: Leica ALS50-II, 70 kHz, scanFreq 50 Hz, scanAngle 60 deg (half),
    // 100 turning pulses; flown at 1500 m above ground.
    LineScannerConfig c;
    c.pulse_rate_hz = 70'000.0;
    c.scan_rate_hz = 50.0;
    c.scan_angle_max_deg = 60.0;
    c.waveform = ScanWaveform::triangle;
    c.turn_duration_s = 100.0 / 70'000.0;
    c.duration_s = 1.0;
    const LineScanner scanner(c);
    const PulseBatch p = all_pulses(scanner);
    ASSERT_EQ(p.size(), 70'000u);
    EXPECT_EQ(scanner.line_of_pulse(69'999), 99u);  // 100 lines/s
    std::vector<std::size_t> per_line(100, 0);
    double lo = 1e9, hi = -1e9;
    for (std::size_t i = 0; i < p.size(); ++i) {
        ++per_line[scanner.line_of_pulse(i)];
        lo = std::min(lo, beam_angle_deg(p.direction[i]));
        hi = std::max(hi, beam_angle_deg(p.direction[i]));
    }
    for (const std::size_t n : per_line) {
        ASSERT_EQ(n, 700u);  // points per line = pulse rate / line rate
    }
    EXPECT_NEAR(hi, 60.0, 1e-9);
    EXPECT_NEAR(lo, -60.0, 1e-9);
    const double swath_m = 2 * 1500.0 * std::tan(60.0 * kDegToRad);  // 5196 m on flat ground
    EXPECT_NEAR(1500.0 * (std::tan(hi * kDegToRad) - std::tan(lo * kDegToRad)), swath_m, 1e-6);
    // The sweep between the turns is 120 deg / (700 - 50) pulses per pulse.
    const double step = beam_angle_deg(p.direction[351]) - beam_angle_deg(p.direction[350]);
    EXPECT_NEAR(step, 120.0 / 650.0, 1e-9);
}

TEST(LineScanner, WaveformNamesRoundTrip) {
    for (const ScanWaveform w :
         {ScanWaveform::sawtooth, ScanWaveform::sinusoid, ScanWaveform::triangle}) {
        EXPECT_EQ(parse_scan_waveform(to_string(w)), w);
    }
    EXPECT_THROW(static_cast<void>(parse_scan_waveform("square")), ConfigError);
}

TEST(LineScanner, ValidationListsEveryProblem) {
    LineScannerConfig c;
    c.pulse_rate_hz = 0.0;
    c.scan_rate_hz = -5.0;
    c.scan_angle_max_deg = 90.0;
    c.duration_s = std::nan("");
    c.start_time_s = INFINITY;
    EXPECT_EQ(c.validate().size(), 5u);
    try {
        LineScanner scanner(c);
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string msg = e.what();
        for (const char* key : {"pulse_rate_hz", "scan_rate_hz", "scan_angle_max_deg", "duration_s",
                                "start_time_s"}) {
            EXPECT_NE(msg.find(key), std::string::npos) << msg;
        }
    }
    LineScannerConfig fast = config(ScanWaveform::sawtooth);
    fast.scan_rate_hz = 60'000.0;  // fewer than two pulses per line
    EXPECT_EQ(fast.validate().size(), 1u);
    LineScannerConfig turn = config(ScanWaveform::sawtooth);
    turn.turn_duration_s = 1e-3;
    EXPECT_EQ(turn.validate().size(), 1u) << "a turn is for the triangle only";
    turn.waveform = ScanWaveform::triangle;
    EXPECT_TRUE(turn.validate().empty());
    turn.turn_duration_s = 0.01;  // a whole line
    EXPECT_EQ(turn.validate().size(), 1u);
    turn.turn_duration_s = -1.0;
    EXPECT_EQ(turn.validate().size(), 1u);
}

}  // namespace
}  // namespace beamtrace
