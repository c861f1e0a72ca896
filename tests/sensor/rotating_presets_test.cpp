// Real sensor presets of the rotating scanner (docs/sensors.md): their beam tables equal the
// documented values, their firing timing and azimuth offsets show in the pulses (closed form),
// and beam tables round-trip through CSV files, whose errors name file, line and column.
#include "beamtrace/sensor/rotating_presets.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/sensor/beam_table.hpp"
#include "sensor/scan_pattern_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(RotatingPresets, BeamTablesEqualTheDocumentedValues) {
    // The numbers below are docs/sensors.md's, written out here, not taken from the library.
    const RotatingScannerConfig vlp = velodyne_vlp16();
    ASSERT_EQ(vlp.beam_elevations_deg.size(), 16u);
    EXPECT_EQ(vlp.beam_elevations_deg[0], -15.0);
    EXPECT_EQ(vlp.beam_elevations_deg[1], 1.0);
    EXPECT_EQ(vlp.beam_elevations_deg[14], -1.0);
    EXPECT_EQ(vlp.beam_elevations_deg[15], 15.0);
    EXPECT_DOUBLE_EQ(vlp.firing_period_s, 55.296e-6);
    ASSERT_EQ(vlp.beam_time_offsets_s.size(), 16u);
    EXPECT_DOUBLE_EQ(vlp.beam_time_offsets_s[1], 2.304e-6);
    EXPECT_DOUBLE_EQ(vlp.beam_time_offsets_s[15], 15 * 2.304e-6);
    EXPECT_TRUE(vlp.spin_clockwise);
    EXPECT_NEAR(vlp.azimuth_step_deg(), 0.1990656, 1e-12);  // 3600 deg/s x 55.296 us

    const RotatingScannerConfig h32 = velodyne_hdl32e();
    ASSERT_EQ(h32.beam_elevations_deg.size(), 32u);
    EXPECT_EQ(h32.beam_elevations_deg[0], -30.67);
    EXPECT_EQ(h32.beam_elevations_deg[1], -9.33);
    // DSR 5 and 6: the manual's table prints -6.66 and -26.66; the 4/3 deg grid (and ROS's
    // standard 32db.yaml) give -6.67 and -26.67, which the preset keeps (docs/sensors.md).
    EXPECT_EQ(h32.beam_elevations_deg[5], -6.67);
    EXPECT_EQ(h32.beam_elevations_deg[6], -26.67);
    EXPECT_EQ(h32.beam_elevations_deg[15], 0.0);
    EXPECT_EQ(h32.beam_elevations_deg[30], -10.67);
    EXPECT_EQ(h32.beam_elevations_deg[31], 10.67);
    EXPECT_DOUBLE_EQ(h32.firing_period_s, 46.08e-6);
    EXPECT_DOUBLE_EQ(h32.beam_time_offsets_s[31], 31 * 1.152e-6);

    const RotatingScannerConfig h64 = velodyne_hdl64e();
    ASSERT_EQ(h64.beam_elevations_deg.size(), 64u);
    ASSERT_EQ(h64.beam_channels.size(), 64u);
    EXPECT_EQ(h64.beam_channels[0], 0);  // upper laser 0 and lower laser 32 fire together
    EXPECT_EQ(h64.beam_channels[1], 32);
    EXPECT_EQ(h64.beam_elevations_deg[0], 2.0);
    EXPECT_EQ(h64.beam_elevations_deg[1], -8.83);
    EXPECT_EQ(h64.beam_time_offsets_s[0], h64.beam_time_offsets_s[1]);
    EXPECT_DOUBLE_EQ(h64.beam_time_offsets_s[2], 50e-6 / 32);
    EXPECT_EQ(h64.beam_channels[63], 63);
    EXPECT_NEAR(h64.beam_elevations_deg[62], 2.0 - 31.0 / 3.0, 1e-12);  // -8.333
    EXPECT_NEAR(h64.beam_elevations_deg[63], -24.33, 1e-12);

    const RotatingScannerConfig os64 = ouster_os1_64();
    ASSERT_EQ(os64.beam_elevations_deg.size(), 64u);
    EXPECT_EQ(os64.beam_elevations_deg[0], 16.611);
    EXPECT_EQ(os64.beam_elevations_deg[2], 15.557);
    EXPECT_EQ(os64.beam_elevations_deg[31], 0.264);
    EXPECT_EQ(os64.beam_elevations_deg[32], -0.264);
    EXPECT_EQ(os64.beam_elevations_deg[63], -16.611);
    // Ouster's beam_azimuth_angles 3.164, 1.055, -1.055, -3.164 (by row modulo 4), negated.
    ASSERT_EQ(os64.beam_azimuth_offsets_deg.size(), 64u);
    EXPECT_EQ(os64.beam_azimuth_offsets_deg[0], -3.164);
    EXPECT_EQ(os64.beam_azimuth_offsets_deg[1], -1.055);
    EXPECT_EQ(os64.beam_azimuth_offsets_deg[2], 1.055);
    EXPECT_EQ(os64.beam_azimuth_offsets_deg[63], 3.164);
    EXPECT_DOUBLE_EQ(os64.firing_rate_hz(), 10240.0);  // 1024 columns x 10 Hz

    const RotatingScannerConfig os128 = ouster_os1_128();
    ASSERT_EQ(os128.beam_elevations_deg.size(), 128u);
    EXPECT_EQ(os128.beam_elevations_deg[0], 22.5);
    EXPECT_EQ(os128.beam_elevations_deg[127], -22.5);
    EXPECT_NEAR(os128.beam_elevations_deg[1], 22.5 - 45.0 / 127, 1e-12);

    for (const RotatingPreset& p : rotating_presets()) {
        EXPECT_TRUE(p.make().validate().empty()) << p.name;
        EXPECT_EQ(find_rotating_preset(p.name), &p);
    }
    EXPECT_EQ(vlp.preset_range_max_m, 100.0);
    EXPECT_EQ(h32.preset_range_m(), (std::pair{0.05, 100.0}));
    EXPECT_EQ(h64.preset_range_max_m, 120.0);
    EXPECT_EQ(vlp16().preset_range_m(), std::nullopt) << "the simplified presets give none";
    EXPECT_EQ(find_rotating_preset("velodyne_vlp16")->facts.wavelength_m, 903e-9);
    EXPECT_EQ(find_rotating_preset("nope"), nullptr);
}

/// The facts of the OS1 data sheet (Gen1): 0.8-120 m for every beam count, 850 nm, and its
/// highest point rates (2048 x 10 or 1024 x 20), twice what the presets' 1024 x 10 fire.
TEST(RotatingPresets, OusterFactsAreTheOs1DataSheets) {
    for (const auto& [name, points] :
         {std::pair{"ouster_os1_64", 1310720.0}, std::pair{"ouster_os1_128", 2621440.0}}) {
        const RotatingPreset* p = find_rotating_preset(name);
        ASSERT_NE(p, nullptr);
        EXPECT_EQ(p->make().preset_range_m(), (std::pair{0.8, 120.0})) << name;
        EXPECT_EQ(p->facts.wavelength_m, 850e-9) << name;
        EXPECT_EQ(p->facts.nominal_points_per_s, points) << name;
        EXPECT_DOUBLE_EQ(p->make().pulse_rate_hz(), points / 2.0) << name;
    }
    EXPECT_EQ(find_rotating_preset("velodyne_hdl32e")->facts.nominal_points_per_s, 700e3);
}

/// Pulse i of a preset fires at start + k * period + offset[b], and (no azimuth offsets, start
/// azimuth 0, clockwise) points at azimuth -rotation rate x 360 x t: the head's angle then.
TEST(RotatingPresets, VelodyneFiringSequenceShowsInTimesAndAzimuths) {
    RotatingScannerConfig c = velodyne_vlp16();
    c.duration_s = 0.01;
    const RotatingScanner scanner(c);
    ASSERT_EQ(scanner.pulse_count(), 16u * 180u);  // floor(0.01 / 55.296 us) = 180 firings
    const PulseBatch p = test::all_pulses(scanner);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t k = i / 16, b = i % 16;
        const double t = static_cast<double>(k) * 55.296e-6 + static_cast<double>(b) * 2.304e-6;
        ASSERT_NEAR(p.time_s[i], t, 1e-15) << i;
        const double azimuth = -3600.0 * t * kDeg;
        const double e = c.beam_elevations_deg[b] * kDeg;
        const Vec3d want{std::cos(e) * std::cos(azimuth), std::cos(e) * std::sin(azimuth),
                         std::sin(e)};
        ASSERT_NEAR(length(p.direction[i] - want), 0.0, 1e-12) << i;
        ASSERT_EQ(p.channel[i], b);
    }
    test::expect_chunking_does_not_matter(scanner, {1, 7, 16, 1000});
}

/// The OS1-64's beam_azimuth_angles put each beam off its column's heading: pulse (column k,
/// row b) points at azimuth -k x 360 / 1024 - beam_azimuth_angles[b], all rows at the column's
/// time; the HDL-64E's channels follow its firing order.
TEST(RotatingPresets, AzimuthOffsetsShowInThePulseDirections) {
    RotatingScannerConfig c = ouster_os1_64();
    c.duration_s = 0.01;
    const RotatingScanner scanner(c);
    const PulseBatch p = test::all_pulses(scanner);
    ASSERT_EQ(p.size(), 64u * 102u);  // 10240 columns/s x 0.01 s = 102.4
    const double ouster_azimuth_deg[4] = {3.164, 1.055, -1.055, -3.164};
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t k = i / 64, b = i % 64;
        const double a =
            (-static_cast<double>(k) * 360.0 / 1024.0 - ouster_azimuth_deg[b % 4]) * kDeg;
        const double e = c.beam_elevations_deg[b] * kDeg;
        const Vec3d want{std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
        ASSERT_NEAR(length(p.direction[i] - want), 0.0, 1e-12) << i;
        ASSERT_NEAR(p.time_s[i], static_cast<double>(k) / 10240.0, 1e-15) << i;
    }
    RotatingScannerConfig h = velodyne_hdl64e();
    h.duration_s = 0.001;
    const PulseBatch q = test::all_pulses(RotatingScanner(h));
    EXPECT_EQ(q.channel[1], 32);
    EXPECT_EQ(q.time_s[0], q.time_s[1]);
    EXPECT_EQ(q.channel[64 + 63], 63);
}

TEST(BeamTableCsv, Os1TableWrittenAndReadBackEqualsThePreset) {
    test::TempDir dir;
    const RotatingScannerConfig preset = ouster_os1_64();
    write_beam_table_csv(dir / "os1.csv", preset);
    RotatingScannerConfig loaded;  // a default head: the table replaces its rows
    read_beam_table_csv(dir / "os1.csv", loaded);
    EXPECT_EQ(loaded.beam_elevations_deg, preset.beam_elevations_deg);
    EXPECT_EQ(loaded.beam_azimuth_offsets_deg, preset.beam_azimuth_offsets_deg);
    EXPECT_EQ(loaded.beam_time_offsets_s, preset.beam_time_offsets_s);
    EXPECT_EQ(loaded.beam_channels.size(), 64u);
    EXPECT_EQ(loaded.beam_channels[63], 63);

    // A table written by hand from the documented numbers, with comments and any column order.
    std::string text = "# OS1-64 design values\nazimuth_offset_deg, elevation_deg\n";
    const double az[4] = {-3.164, -1.055, 1.055, 3.164};
    for (std::size_t b = 0; b < 64; ++b) {
        char row[64];  // the elevations as the data sheet prints them, 3 decimals
        std::snprintf(row, sizeof row, "%.3f,%.3f\n", az[b % 4], preset.beam_elevations_deg[b]);
        text += row;
    }
    test::write_file(dir / "hand.csv", text);
    RotatingScannerConfig hand;
    read_beam_table_csv(dir / "hand.csv", hand);
    EXPECT_EQ(hand.beam_elevations_deg, preset.beam_elevations_deg);
    ASSERT_EQ(hand.beam_azimuth_offsets_deg.size(), 64u);
    EXPECT_DOUBLE_EQ(hand.beam_azimuth_offsets_deg[5], preset.beam_azimuth_offsets_deg[5]);
    EXPECT_TRUE(hand.beam_time_offsets_s.empty());
}

TEST(RotatingPresets, TimingTablesAreValidated) {
    RotatingScannerConfig c = velodyne_vlp16();
    EXPECT_TRUE(c.validate().empty());
    c.beam_time_offsets_s[3] = c.beam_time_offsets_s[2] - 1e-7;  // out of firing order
    ASSERT_EQ(c.validate().size(), 1u);
    EXPECT_NE(c.validate()[0].find("beam_time_offsets_s[3] must not be earlier"),
              std::string::npos);
    c = velodyne_vlp16();
    c.beam_time_offsets_s[15] = 55.296e-6;  // the next firing's start
    ASSERT_EQ(c.validate().size(), 1u);
    EXPECT_NE(c.validate()[0].find("beam_time_offsets_s[15] must be in [0, firing period"),
              std::string::npos);
    c = velodyne_vlp16();
    c.beam_time_offsets_s.pop_back();
    EXPECT_EQ(c.validate().size(), 1u);
    c = velodyne_hdl64e();
    c.beam_channels[1] = 0;
    ASSERT_EQ(c.validate().size(), 1u);
    EXPECT_EQ(c.validate()[0], "beam_channels must be distinct");
    c = velodyne_vlp16();
    c.firing_period_s = -1.0;
    EXPECT_FALSE(c.validate().empty());
    c = velodyne_vlp16();
    c.rotation_rate_hz = 20.0;  // the same clock, twice the azimuth step
    EXPECT_NEAR(c.azimuth_step_deg(), 2 * 0.1990656, 1e-12);
    EXPECT_DOUBLE_EQ(c.firing_rate_hz(), 1.0 / 55.296e-6);
}

std::string csv_error(const test::TempDir& dir, const std::string& text) {
    test::write_file(dir / "t.csv", text);
    RotatingScannerConfig c;
    try {
        read_beam_table_csv(dir / "t.csv", c);
    } catch (const InputError& e) {
        return e.what();
    }
    ADD_FAILURE() << "accepted: " << text.substr(0, 200);
    return {};
}

TEST(BeamTableCsv, ErrorsNameFileLineAndColumn) {
    test::TempDir dir;
    const std::string f = (dir / "t.csv").string();
    EXPECT_EQ(csv_error(dir, "elevation_deg,azimuth_offset_deg\n1,2\n3,x\n"),
              f + ":3: column 2 (azimuth_offset_deg): expected a finite number, got 'x'");
    EXPECT_EQ(csv_error(dir, "# c\nelevation_deg,bogus\n"),
              f + ":2: unknown column 'bogus' in the header (expected elevation_deg, "
                  "azimuth_offset_deg, time_offset_s, channel)");
    EXPECT_EQ(csv_error(dir, "azimuth_offset_deg\n1\n"),
              f + ":1: the header must name an elevation_deg column");
    EXPECT_EQ(csv_error(dir, "elevation_deg,channel\n1,2,3\n"), f + ":2: expected 2 fields, got 3");
    EXPECT_EQ(csv_error(dir, "elevation_deg,channel\n1,70000\n"),
              f + ":2: column 2 (channel): expected a channel number 0-65535, got '70000'");
    EXPECT_EQ(csv_error(dir, "elevation_deg\n91\n"),
              f + ":2: column 1 (elevation_deg): must be in [-90, 90] degrees");
    EXPECT_NE(csv_error(dir, "elevation_deg\n").find("no beam rows"), std::string::npos);
    std::string many = "elevation_deg\n";
    for (std::size_t i = 0; i <= kMaxBeamTableRows; ++i) {
        many += "0\n";
    }
    EXPECT_EQ(csv_error(dir, many), f + ":65538: more than 65536 rows, the limit for a beam table");
    const std::string huge(kMaxBeamTableBytes + 1, '\n');
    EXPECT_NE(csv_error(dir, huge).find("4 MiB"), std::string::npos);
}

}  // namespace
}  // namespace beamtrace
