// LAS 1.4 wave packets (formats 9, 10): points.las with its points.wdp or its Waveform Data
// Packets EVLR, read back by our LasWavePacketReader (the samples the physics produced, within the
// documented quantisation step g / 2) and by an independent parse of the raw bytes written from
// the LAS 1.4 R15 tables (header fields, VLR walk, descriptor layout, EVLR header, the format 9
// record's bytes 30-58), not through the writer's code. Plus Leica's PDRF 4 file, and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/las_wave_packets.hpp"
#include "beamtrace/io/point_sink_registry.hpp"
#include "beamtrace/physics/waveform.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

constexpr double kThresholdW = 1e-8;
constexpr double kGainW = kThresholdW / 64;  // docs/formats.md
constexpr double kBinNs = 0.5;

template <typename T>
T at(const std::string& b, std::size_t offset) {
    EXPECT_LE(offset + sizeof(T), b.size());
    T v{};
    if (offset + sizeof(T) <= b.size()) {
        std::memcpy(&v, b.data() + offset, sizeof v);
    }
    return v;
}

/// A pulse as the physics leaves it: beam origin and axis, first bin, float samples.
struct Pulse {
    Vec3d origin, axis;
    std::int64_t first_bin = 0;
    std::vector<float> samples;
};

/// Two blocks of pulses: several sample counts (descriptor sizes), a pulse with no points, a
/// pulse with no samples, two returns sharing one packet.
std::vector<PointBlock> make_blocks(std::vector<Pulse>& pulses) {
    std::vector<PointBlock> blocks(2);
    const std::uint32_t counts[] = {5, 20, 40, 0, 9, 130};
    const int returns[] = {2, 0, 1, 1, 1, 3};
    for (std::size_t i = 0; i < 6; ++i) {
        PointBlock& b = blocks[i / 3];
        Pulse p;
        p.origin = {10.0 + static_cast<double>(i), -3.0, 150.0};
        p.axis = normalize(Vec3d{0.1 * static_cast<double>(i), 0.2, -1.0});
        p.first_bin = 1000 + 7 * static_cast<std::int64_t>(i);
        for (std::uint32_t k = 0; k < counts[i]; ++k) {
            p.samples.push_back(static_cast<float>(3e-7 * std::exp(-0.1 * (k - 3.0) * (k - 3.0)) +
                                                   1e-9 * static_cast<double>(i)));
        }
        b.waveforms.push_back({i, 0.001 * static_cast<double>(i), p.origin, p.axis, p.first_bin,
                               b.samples.size(), counts[i]});
        b.samples.insert(b.samples.end(), p.samples.begin(), p.samples.end());
        for (int r = 0; r < returns[i]; ++r) {
            BlockPoint q;
            q.range_m = static_cast<float>((static_cast<double>(p.first_bin) + 2.0 + 1.5 * r) *
                                           kBinNs * 1e-9 * kSpeedOfLight_m_per_s / 2);
            const Vec3d xyz = p.origin + p.axis * static_cast<double>(q.range_m);
            q.x = xyz.x;
            q.y = xyz.y;
            q.z = xyz.z;
            q.gps_time = 0.001 * static_cast<double>(i);
            q.return_number = static_cast<std::uint8_t>(r + 1);
            q.number_of_returns = static_cast<std::uint8_t>(returns[i]);
            q.pulse = i;
            b.points.push_back(q);
        }
        pulses.push_back(p);
    }
    return blocks;
}

/// Writes points.las (format `format`) through the registry's LAS sink.
void write_sink(const fs::path& dir, int format, LasWaveformStorage storage,
                std::vector<Pulse>& pulses) {
    SinkFacts facts;
    facts.output_dir = dir;
    facts.lo_m = {-100, -100, -100};
    facts.hi_m = {200, 200, 200};
    facts.las_point_format = format;
    facts.waveform = WaveformFacts{kBinNs, 4.0, kThresholdW, 1000.0, storage};
    auto sink = point_sink("las").make(facts);
    for (const PointBlock& b : make_blocks(pulses)) {
        auto buffer = sink->make_buffer();
        sink->encode(b, *buffer);
        sink->write(*buffer);
    }
    (void)sink->commit();
}

/// The pulse of each point, in file order (make_blocks' order).
std::vector<std::size_t> point_pulses() {
    return {0, 0, 2, 3, 4, 5, 5, 5};
}

class WavePackets : public ::testing::TestWithParam<std::tuple<int, LasWaveformStorage>> {};

TEST_P(WavePackets, OurReaderReturnsThePhysicsSamples) {
    const auto [format, storage] = GetParam();
    test::TempDir dir;
    std::vector<Pulse> pulses;
    write_sink(dir.path(), format, storage, pulses);
    EXPECT_EQ(fs::exists(dir / "points.wdp"), storage == LasWaveformStorage::external);
    LasReader reader(dir / "points.las");
    EXPECT_EQ(reader.header().point_format, format);
    LasWavePacketReader waves(reader);
    EXPECT_EQ(waves.descriptors().size(), 22u);
    const auto points = read_las_points(dir / "points.las");
    const auto pulse_of = point_pulses();
    ASSERT_EQ(points.size(), pulse_of.size());
    std::vector<double> w;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const Pulse& p = pulses[pulse_of[i]];
        waves.samples(points[i], w);
        if (p.samples.empty()) {
            EXPECT_EQ(points[i].wave_descriptor_index, 0);
            EXPECT_TRUE(w.empty());
            continue;
        }
        ASSERT_GE(w.size(), p.samples.size()) << i;
        for (std::size_t k = 0; k < w.size(); ++k) {
            const double want = k < p.samples.size() ? p.samples[k] : 0.0;
            ASSERT_NEAR(w[k], want, kGainW / 2 * 1.0001) << "point " << i << " sample " << k;
        }
    }
}

/// The independent parse: the bytes against the LAS 1.4 R15 tables.
TEST_P(WavePackets, DescriptorsAndOffsetsFollowTheSpecification) {
    const auto [format, storage] = GetParam();
    test::TempDir dir;
    std::vector<Pulse> pulses;
    write_sink(dir.path(), format, storage, pulses);
    const std::string las = test::read_file(dir / "points.las");
    const bool internal = storage == LasWaveformStorage::internal;
    // Public header block.
    ASSERT_EQ(las.substr(0, 4), "LASF");
    EXPECT_EQ(las[24], 1);
    EXPECT_EQ(las[25], 4);
    const auto encoding = at<std::uint16_t>(las, 6);
    EXPECT_EQ((encoding >> 1) & 1, internal ? 1 : 0) << "bit 1: packets inside";
    EXPECT_EQ((encoding >> 2) & 1, internal ? 0 : 1) << "bit 2: packets in the .wdp";
    const auto header_size = at<std::uint16_t>(las, 94);
    const auto point_data = at<std::uint32_t>(las, 96);
    const auto vlr_count = at<std::uint32_t>(las, 100);
    EXPECT_EQ(static_cast<int>(static_cast<std::uint8_t>(las[104])), format);
    const auto record = at<std::uint16_t>(las, 105);
    EXPECT_EQ(record, format == 9 ? 59 : 67);
    const auto start_of_waveform = at<std::uint64_t>(las, 227);
    const auto first_evlr = at<std::uint64_t>(las, 235);
    const auto evlr_count = at<std::uint32_t>(las, 243);
    const auto point_count = at<std::uint64_t>(las, 247);
    ASSERT_EQ(point_count, point_pulses().size());
    // VLR walk: the descriptors (LASF_Spec, record 100-354, 26 bytes each).
    struct Descriptor {
        unsigned bits, compression;
        std::uint32_t samples, spacing;
        double gain, offset;
    };
    std::map<int, Descriptor> descriptors;
    std::size_t pos = header_size;
    for (std::uint32_t v = 0; v < vlr_count; ++v) {
        const std::string user = las.substr(pos + 2, 16).c_str();
        const auto id = at<std::uint16_t>(las, pos + 18);
        const auto length = at<std::uint16_t>(las, pos + 20);
        if (user == "LASF_Spec" && id >= 100 && id <= 354) {
            EXPECT_EQ(length, 26);
            const std::size_t d = pos + 54;
            descriptors[id - 99] = {
                static_cast<std::uint8_t>(las[d]), static_cast<std::uint8_t>(las[d + 1]),
                at<std::uint32_t>(las, d + 2),     at<std::uint32_t>(las, d + 6),
                at<double>(las, d + 10),           at<double>(las, d + 18)};
        }
        pos += 54 + length;
    }
    EXPECT_EQ(pos, point_data);
    ASSERT_FALSE(descriptors.empty());
    for (const auto& [index, d] : descriptors) {
        EXPECT_EQ(d.bits, 32u);
        EXPECT_EQ(d.compression, 0u);
        EXPECT_EQ(d.spacing, 500u) << "picoseconds";
        EXPECT_DOUBLE_EQ(d.gain, kGainW);
        EXPECT_EQ(d.offset, 0.0);
    }
    // The Waveform Data Packets record: an EVLR (LASF_Spec / 65535), or the .wdp's header.
    const std::string wdp = internal ? std::string() : test::read_file(dir / "points.wdp");
    const std::string& data = internal ? las : wdp;
    const std::size_t record_at = internal ? start_of_waveform : 0;
    const std::size_t points_end = point_data + point_count * record;
    if (internal) {
        EXPECT_EQ(evlr_count, 1u);
        EXPECT_EQ(first_evlr, points_end);
        EXPECT_EQ(start_of_waveform, points_end);
    } else {
        EXPECT_EQ(start_of_waveform, 0u) << "external packets: the field must be zero";
        EXPECT_EQ(evlr_count, 0u);
        EXPECT_EQ(las.size(), points_end);
    }
    EXPECT_EQ(std::string(data.substr(record_at + 2, 16).c_str()), "LASF_Spec");
    EXPECT_EQ(at<std::uint16_t>(data, record_at + 18), 65535);
    EXPECT_EQ(at<std::uint64_t>(data, record_at + 20), data.size() - record_at - 60);
    // Every point record: bytes 30 (format 9) or 38 (format 10) on.
    const std::size_t w = format == 9 ? 30 : 38;
    const auto pulse_of = point_pulses();
    const double scale[3] = {at<double>(las, 131), at<double>(las, 139), at<double>(las, 147)};
    const double offs[3] = {at<double>(las, 155), at<double>(las, 163), at<double>(las, 171)};
    for (std::size_t i = 0; i < point_count; ++i) {
        const std::size_t r = point_data + i * record;
        const Pulse& p = pulses[pulse_of[i]];
        const int index = static_cast<std::uint8_t>(las[r + w]);
        const auto offset = at<std::uint64_t>(las, r + w + 1);
        const auto size = at<std::uint32_t>(las, r + w + 9);
        const auto location = at<float>(las, r + w + 13);
        const double d[3] = {at<float>(las, r + w + 17), at<float>(las, r + w + 21),
                             at<float>(las, r + w + 25)};
        if (p.samples.empty()) {
            EXPECT_EQ(index, 0) << "no waveform: index 0";
            continue;
        }
        ASSERT_TRUE(descriptors.count(index)) << "point " << i << ": index " << index;
        const Descriptor& desc = descriptors[index];
        EXPECT_GE(desc.samples, p.samples.size());
        EXPECT_EQ(size, desc.samples * desc.bits / 8);
        ASSERT_GE(offset, 60u) << "offsets count from the record's header";
        ASSERT_LE(record_at + offset + size, data.size());
        for (std::size_t k = 0; k < desc.samples; ++k) {
            const double v =
                desc.offset + desc.gain * at<std::uint32_t>(data, record_at + offset + 4 * k);
            const double want = k < p.samples.size() ? p.samples[k] : 0.0;
            ASSERT_NEAR(v, want, kGainW / 2 * 1.0001) << "point " << i << " sample " << k;
        }
        // Return point location: picoseconds from the first sample to the point.
        double xp[3];
        for (int k = 0; k < 3; ++k) {
            xp[k] = at<std::int32_t>(las, r + 4 * k) * scale[k] + offs[k];
        }
        const Vec3d point{xp[0], xp[1], xp[2]};
        const double range = length(point - p.origin);
        const double first_ps = static_cast<double>(p.first_bin) * desc.spacing;
        EXPECT_NEAR(location, range * 2e12 / kSpeedOfLight_m_per_s - first_ps, 20.0);
        // (dx, dy, dz): c / 2 per picosecond, from the target back to the sensor; the anchor
        // X_0 = X_P + L d is the first sample, at the first bin's round-trip time.
        const Vec3d dv{d[0], d[1], d[2]};
        EXPECT_NEAR(length(dv), kSpeedOfLight_m_per_s / 2 * 1e-12, 1e-10);
        EXPECT_NEAR(dot(dv, p.axis) / length(dv), -1.0, 1e-6);
        const Vec3d anchor = point + dv * static_cast<double>(location);
        const Vec3d first = p.origin + p.axis * (first_ps * 1e-12 * kSpeedOfLight_m_per_s / 2);
        EXPECT_NEAR(length(anchor - first), 0.0, 0.003) << "point " << i;
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, WavePackets,
                         ::testing::Values(std::tuple{9, LasWaveformStorage::external},
                                           std::tuple{9, LasWaveformStorage::internal},
                                           std::tuple{10, LasWaveformStorage::external},
                                           std::tuple{10, LasWaveformStorage::internal}));

/// A survey with physics.waveform.keep: every point's packet holds its pulse's samples of
/// waveforms.bin (the float32 samples the physics produced), within g / 2.
TEST(WavePacketSurvey, PacketsHoldTheSamplesOfWaveformsBin) {
    test::TempDir dir;
    const std::string yaml = R"(scene: demo
scanner: {type: line, pulse_rate_hz: 20000, scan_rate_hz: 20, scan_angle_max_deg: 25,
          waveform: triangle, duration_s: 0.02}
platform: {type: legs, speed_mps: 50, waypoints_m: [[-30, 0, 150], [30, 0, 150]]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 2, rings: 1}
  returns: {mode: all, max: 5}
  waveform: {pulse_fwhm_ns: 2, bin_ns: 0.5, keep: true}
output: {wave_packets: evlr}
)";
    test::run_survey_in(yaml, dir, 2, 1 << 16, 7);
    // waveforms.bin: pulse records keyed by GPS time (docs/survey.md).
    const std::string bin = test::read_file(dir / "out" / "waveforms.bin");
    std::map<double, std::vector<float>> by_time;
    for (std::size_t pos = 32; pos + 76 <= bin.size();) {
        const auto n = at<std::uint32_t>(bin, pos + 72);
        std::vector<float> s(n);
        std::memcpy(s.data(), bin.data() + pos + 76, 4u * n);
        by_time[at<double>(bin, pos + 8)] = std::move(s);
        pos += 76 + 4u * n;
    }
    LasReader reader(dir / "out" / "points.las");
    EXPECT_EQ(reader.header().point_format, 9);
    LasWavePacketReader waves(reader);
    const auto points = read_las_points(dir / "out" / "points.las");
    ASSERT_GT(points.size(), 100u);
    std::vector<double> w;
    for (const LasPoint& p : points) {
        ASSERT_TRUE(by_time.count(p.gps_time));
        const auto& want = by_time[p.gps_time];
        waves.samples(p, w);
        ASSERT_GE(w.size(), want.size());
        for (std::size_t k = 0; k < w.size(); ++k) {
            ASSERT_NEAR(w[k], k < want.size() ? want[k] : 0.0f, kGainW / 2 * 1.0001);
        }
    }
}

/// Leica's LAS 1.3 PDRF 4 file (laspy's test data): its descriptor and wave packet fields, and
/// its packets, cut off after 100 bytes of data, refused by name.
TEST(WavePacketFiles, LeicaPdrf4FileReadsAndItsTruncatedPacketsAreRefused) {
    const fs::path path = test::shared_data("las/las/simple1_3.las");
    BEAMTRACE_REQUIRE_FILE(path);
    LasReader reader(path);
    LasWavePacketReader waves(reader);
    ASSERT_EQ(waves.descriptors().size(), 1u);
    const LasWavePacketDescriptor& d = waves.descriptor(1);
    EXPECT_EQ(d.bits_per_sample, 8);
    EXPECT_EQ(d.compression, 0);
    EXPECT_EQ(d.samples, 256u);
    EXPECT_EQ(d.spacing_ps, 1000u);
    EXPECT_NEAR(d.gain, 0.0172906, 1e-6);
    EXPECT_EQ(waves.data_path(), path);
    EXPECT_EQ(waves.data_bytes(), 100u);
    const auto points = read_las_points(path);
    ASSERT_EQ(points.size(), 999u);
    EXPECT_EQ(points[0].wave_descriptor_index, 1);
    EXPECT_EQ(points[0].wave_data_offset, 316u);
    EXPECT_EQ(points[0].wave_packet_size, 256u);
    EXPECT_FLOAT_EQ(points[0].wave_return_location, 22493.254f);
    // Airborne: (dx, dy, dz) points up, back to the sensor, c / 2 per picosecond.
    const Vec3d dv{points[0].wave_dx, points[0].wave_dy, points[0].wave_dz};
    EXPECT_GT(dv.z, 0.0);
    EXPECT_NEAR(length(dv), kSpeedOfLight_m_per_s / 2 * 1e-12, 1e-7);
    std::vector<double> w;
    test::expect_input_error(
        [&](const fs::path&) {
            waves.samples(points[0], w);
            return 0;
        },
        path, "outside the waveform data");
}

/// fullwave.laz (YellowScan, PDRF 10 LAZ, packets in a .wdp that is not shipped).
TEST(WavePacketFiles, FullwaveLazDescriptorsAndItsMissingWdpFile) {
    const fs::path path = test::shared_data("las/laz/fullwave.laz");
    BEAMTRACE_REQUIRE_FILE(path);
    std::unique_ptr<LasReader> reader;
    try {
        reader = std::make_unique<LasReader>(path);
    } catch (const InputError& e) {
        BEAMTRACE_SKIP_OR_FAIL("the LAZ reader refuses it: " << e.what());
    }
    const auto descriptors = las_wave_packet_descriptors(reader->vlrs(), path);
    ASSERT_FALSE(descriptors.empty());
    EXPECT_GT(descriptors[0].samples, 0u);
    EXPECT_GT(descriptors[0].spacing_ps, 0u);
    test::expect_input_error([&](const fs::path&) { return LasWavePacketReader(*reader); }, path,
                             ".wdp");
}

/// Bad input: a descriptor index with no descriptor, an offset past the packet data.
TEST(WavePacketFiles, BadIndexAndOffsetGiveInputErrorsNamingTheFile) {
    test::TempDir dir;
    std::vector<Pulse> pulses;
    write_sink(dir.path(), 9, LasWaveformStorage::internal, pulses);
    std::string las = test::read_file(dir / "points.las");
    const auto point_data = at<std::uint32_t>(las, 96);
    const auto patch = [&](const std::string& name, std::size_t field, const void* v,
                           std::size_t n) {
        std::string copy = las;
        std::memcpy(copy.data() + point_data + 30 + field, v, n);
        return test::write_file(dir / name, copy);
    };
    const std::uint8_t bad_index = 200;
    const fs::path a = patch("bad_index.las", 0, &bad_index, 1);
    const std::uint64_t far = std::uint64_t{1} << 40;
    const fs::path b = patch("bad_offset.las", 1, &far, 8);
    for (const auto& [path, fragment] :
         {std::pair{a, "descriptor index 200"}, std::pair{b, "outside the waveform data"}}) {
        test::expect_input_error(
            [&](const fs::path& p) {
                LasReader reader(p);
                LasWavePacketReader waves(reader);
                std::vector<double> w;
                waves.samples(read_las_points(p)[0], w);
                return 0;
            },
            path, fragment);
    }
}

}  // namespace
}  // namespace beamtrace
