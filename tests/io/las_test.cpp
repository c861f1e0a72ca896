// LasWriter round trips through LasReader, and the reader's checks on deliberately broken files.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <random>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "corruption_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

using test::entry_count;
using test::write_file;

/// `n` points with every field of `format` set to varied in-range values (fields the format does
/// not store are left 0, as the reader returns them).
std::vector<LasPoint> make_points(std::size_t n, int format, std::size_t extra_bytes = 0) {
    std::vector<LasPoint> points(n);
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> coord(-500.0, 500.0);
    for (std::size_t i = 0; i < n; ++i) {
        LasPoint& p = points[i];
        p.x = 635000.0 + coord(rng);
        p.y = 4850000.0 + coord(rng);
        p.z = 100.0 + coord(rng) * 0.1;
        p.intensity = static_cast<std::uint16_t>(i * 7919);
        p.number_of_returns = static_cast<std::uint8_t>(1 + i % 15);
        p.return_number = static_cast<std::uint8_t>(1 + (i * 7) % p.number_of_returns);
        p.classification = static_cast<std::uint8_t>(i % 256);
        p.synthetic = (i & 1) != 0;
        p.key_point = (i & 2) != 0;
        p.withheld = (i & 4) != 0;
        p.overlap = (i & 8) != 0;
        p.scanner_channel = static_cast<std::uint8_t>((i >> 4) % 4);
        p.scan_direction = (i & 64) != 0;
        p.edge_of_flight_line = (i & 128) != 0;
        const int angle_steps = static_cast<int>((i * 37) % 60001) - 30000;
        p.scan_angle_deg = static_cast<float>(angle_steps * 0.006);
        p.user_data = static_cast<std::uint8_t>(i * 3);
        p.point_source_id = static_cast<std::uint16_t>(i * 11);
        p.gps_time = 1.3e9 + static_cast<double>(i) * 1.25e-5;
        if (las_format_has_rgb(format)) {
            p.red = static_cast<std::uint16_t>(i * 13);
            p.green = static_cast<std::uint16_t>(i * 17);
            p.blue = static_cast<std::uint16_t>(i * 19);
        }
        if (las_format_has_nir(format)) {
            p.nir = static_cast<std::uint16_t>(i * 23);
        }
        for (std::size_t k = 0; k < extra_bytes; ++k) {
            p.extra_bytes.push_back(static_cast<std::uint8_t>(i + k));
        }
    }
    return points;
}

double quantized(double v, double scale, double offset) {
    return std::round((v - offset) / scale) * scale + offset;
}

/// Expects `got` to equal `want` field by field, xyz within half a scale step.
void expect_same_point(const LasPoint& got, const LasPoint& want, const Vec3d& scale,
                       std::size_t i) {
    EXPECT_NEAR(got.x, want.x, 0.5 * scale.x + 1e-9) << i;
    EXPECT_NEAR(got.y, want.y, 0.5 * scale.y + 1e-9) << i;
    EXPECT_NEAR(got.z, want.z, 0.5 * scale.z + 1e-9) << i;
    LasPoint a = got;
    a.x = want.x;
    a.y = want.y;
    a.z = want.z;
    EXPECT_EQ(a, want) << "point " << i;
}

class LasWriterTest : public test::TempDirTest {};

class LasWriterFormat : public LasWriterTest, public ::testing::WithParamInterface<int> {};

TEST_P(LasWriterFormat, RoundTripsEveryFieldAndFinalizesTheHeader) {
    const int format = GetParam();
    // More than one 64k chunk, written in uneven pieces.
    const auto points = make_points(150001, format, format == 8 ? 3 : 0);
    LasWriterConfig config = las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200});
    config.point_format = format;
    config.extra_bytes_per_point = format == 8 ? 3 : 0;
    config.gps_time_is_standard = format != 7;
    config.creation_day_of_year = 42;
    config.creation_year = 2024;
    config.vlrs.push_back({"beamtrace", 1, "scene description", {1, 2, 3, 4, 5}, false, 0});
    config.vlrs.push_back(
        {"beamtrace", 2, "a big record", std::vector<std::uint8_t>(70000, 7), true, 0});
    const fs::path path = dir_ / "out.las";
    {
        LasWriter writer(path, config);
        std::size_t done = 0;
        for (std::size_t piece = 1; done < points.size(); piece *= 3) {
            const std::size_t n = std::min(piece, points.size() - done);
            writer.write(std::span(points).subspan(done, n));
            done += n;
        }
        EXPECT_FALSE(fs::exists(path));
        EXPECT_EQ(writer.point_count(), points.size());
        writer.close();
    }
    ASSERT_TRUE(fs::exists(path));
    EXPECT_EQ(entry_count(dir_.path()), 1u);

    LasReader reader(path);
    const LasHeader& h = reader.header();
    EXPECT_EQ(h.version_major, 1);
    EXPECT_EQ(h.version_minor, 4);
    EXPECT_EQ(h.header_size, 375);
    EXPECT_EQ(h.point_format, format);
    EXPECT_EQ(h.point_record_length, las_point_record_size(format) + config.extra_bytes_per_point);
    EXPECT_EQ(h.point_count, points.size());
    EXPECT_EQ(h.legacy_point_count, 0u);  // required for formats 6-10
    EXPECT_EQ(h.gps_time_is_standard(), format != 7);
    EXPECT_TRUE(h.crs_is_wkt());
    EXPECT_EQ(h.system_identifier, "beamtrace");
    EXPECT_EQ(h.generating_software, "beamtrace " BEAMTRACE_VERSION);
    EXPECT_EQ(h.creation_day_of_year, 42);
    EXPECT_EQ(h.creation_year, 2024);
    EXPECT_EQ(h.scale, config.scale);
    EXPECT_EQ(h.offset, config.offset);
    EXPECT_EQ(h.number_of_vlrs, 1u);
    EXPECT_EQ(h.number_of_evlrs, 1u);
    EXPECT_EQ(h.offset_to_point_data, 375u + 54u + 5u);

    std::array<std::uint64_t, 15> by_return{};
    Vec3d lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& p : points) {
        ++by_return[p.return_number - 1u];
        const Vec3d q{quantized(p.x, h.scale.x, h.offset.x), quantized(p.y, h.scale.y, h.offset.y),
                      quantized(p.z, h.scale.z, h.offset.z)};
        lo = min(lo, q);
        hi = max(hi, q);
    }
    EXPECT_EQ(h.points_by_return, by_return);
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_DOUBLE_EQ(h.min[k], lo[k]) << k;
        EXPECT_DOUBLE_EQ(h.max[k], hi[k]) << k;
    }

    ASSERT_EQ(reader.vlrs().size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const LasVlr& got = reader.vlrs()[i];
        EXPECT_EQ(got.user_id, config.vlrs[i].user_id);
        EXPECT_EQ(got.record_id, config.vlrs[i].record_id);
        EXPECT_EQ(got.description, config.vlrs[i].description);
        EXPECT_EQ(got.data, config.vlrs[i].data);
        EXPECT_EQ(got.extended, config.vlrs[i].extended);
        EXPECT_EQ(got.length, config.vlrs[i].data.size());
    }

    // Stream back in chunks that do not divide the reader's.
    std::vector<LasPoint> chunk(9999);
    std::size_t index = 0;
    while (const std::size_t n = reader.read(chunk)) {
        for (std::size_t i = 0; i < n; ++i, ++index) {
            expect_same_point(chunk[i], points[index], h.scale, index);
            if (HasFailure()) {
                return;
            }
        }
    }
    EXPECT_EQ(index, points.size());
    EXPECT_EQ(reader.points_remaining(), 0u);

    // Seeking restarts anywhere.
    reader.seek(123456);
    ASSERT_EQ(reader.read(std::span(chunk).first(2)), 2u);
    expect_same_point(chunk[0], points[123456], h.scale, 123456);
    expect_same_point(chunk[1], points[123457], h.scale, 123457);
}

INSTANTIATE_TEST_SUITE_P(Las, LasWriterFormat, ::testing::Values(6, 7, 8));

TEST_F(LasWriterTest, ZeroPointsGiveAValidEmptyFile) {
    const fs::path path = dir_ / "empty.las";
    LasWriter writer(path, {});
    writer.close();
    LasReader reader(path);
    EXPECT_EQ(reader.header().point_count, 0u);
    EXPECT_EQ(reader.header().min, Vec3d(0, 0, 0));
    EXPECT_EQ(reader.header().max, Vec3d(0, 0, 0));
    EXPECT_EQ(reader.header().points_by_return, (std::array<std::uint64_t, 15>{}));
    EXPECT_TRUE(reader.vlrs().empty());
    std::vector<LasPoint> chunk(10);
    EXPECT_EQ(reader.read(chunk), 0u);
    EXPECT_EQ(fs::file_size(path), 375u);
}

TEST_F(LasWriterTest, OutOfRangeCoordinateThrowsAndLeavesNoFile) {
    const fs::path path = dir_ / "far.las";
    std::vector<LasPoint> points(3);
    points[0].return_number = points[0].number_of_returns = 1;
    points[2].y = 1e7;  // 1e10 millimetre steps
    LasWriter writer(path, {});
    try {
        writer.write(points);
        FAIL() << "expected OutputError";
    } catch (const OutputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(path.string()), std::string::npos) << message;
        EXPECT_NE(message.find("point 2: y = 10000000"), std::string::npos) << message;
    }
    EXPECT_THROW(writer.close(), OutputError);
    EXPECT_EQ(entry_count(dir_.path()), 0u);
}

TEST_F(LasWriterTest, NaNCoordinateAndBadFieldsThrow) {
    const auto attempt = [&](auto&& change, const char* fragment) {
        std::vector<LasPoint> points(1);
        change(points[0]);
        LasWriter writer(dir_ / "bad.las", {});
        try {
            writer.write(points);
            ADD_FAILURE() << "expected OutputError with " << fragment;
        } catch (const OutputError& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    attempt([](LasPoint& p) { p.z = std::nan(""); }, "z = nan");
    attempt([](LasPoint& p) { p.return_number = 16; }, "return 16 of 0");
    attempt([](LasPoint& p) { p.scanner_channel = 4; }, "scanner channel 4");
    attempt([](LasPoint& p) { p.scan_angle_deg = 181.0f; }, "scan angle 181");
    attempt([](LasPoint& p) { p.extra_bytes = {1}; }, "1 extra bytes, expected 0");
    EXPECT_EQ(entry_count(dir_.path()), 0u);
}

TEST_F(LasWriterTest, BlocksEncodedApartGiveTheSameFileAsPointByPoint) {
    const auto points = make_points(200000, 7);
    LasWriterConfig config = las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200});
    config.point_format = 7;
    config.creation_day_of_year = 100;
    config.creation_year = 2026;
    {
        LasWriter one(dir_ / "one.las", config);
        one.write(std::span(points).first(1000));  // mixed: some points one by one first
        for (std::size_t i = 1000; i < points.size(); ++i) {
            one.write(std::span(points).subspan(i, 1));
        }
        one.close();
    }
    {
        LasWriter blocks(dir_ / "blocks.las", config);
        blocks.write(std::span(points).first(1000));
        // Blocks of uneven sizes, encoded out of order (as pool threads would), written in order.
        std::vector<LasRecordBlock> parts(7);
        const std::size_t step = (points.size() - 1000) / parts.size() + 1;
        for (std::size_t k = parts.size(); k-- > 0;) {
            const std::size_t b = 1000 + k * step;
            const std::size_t e = std::min(points.size(), b + step);
            for (std::size_t i = b; i < e; ++i) {
                blocks.encode(points[i], parts[k]);
            }
        }
        blocks.write_block(LasRecordBlock{});  // empty blocks are fine
        for (const auto& part : parts) {
            blocks.write_block(part);
        }
        EXPECT_EQ(blocks.point_count(), points.size());
        blocks.close();
    }
    EXPECT_EQ(test::read_file(dir_ / "one.las"), test::read_file(dir_ / "blocks.las"));
}

TEST_F(LasWriterTest, SimplePointsEncodeLikeTheSameLasPointsEvenInReusedBlocks) {
    LasWriterConfig config = las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200});
    config.point_format = 8;
    LasWriter writer(dir_ / "x.las", config);
    // A block that held a full LasPoint (colours, NIR, flags) is reused for a simple point.
    LasPoint full = make_points(1, 8)[0];
    full.red = full.green = full.blue = full.nir = 0xABCD;
    full.synthetic = full.overlap = true;
    LasRecordBlock reused;
    writer.encode(full, reused);
    reused.clear();
    LasSimplePoint s;
    s.x = 635123.456;
    s.y = 4850001.5;
    s.z = 101.25;
    s.gps_time = 12345.678;
    s.scan_angle_deg = -17.25f;
    s.intensity = 999;
    s.point_source_id = 42;
    s.return_number = 2;
    s.number_of_returns = 3;
    s.classification = 6;
    s.user_data = 63;
    writer.encode(s, reused);
    LasPoint same;
    same.x = s.x;
    same.y = s.y;
    same.z = s.z;
    same.gps_time = s.gps_time;
    same.scan_angle_deg = s.scan_angle_deg;
    same.intensity = s.intensity;
    same.point_source_id = s.point_source_id;
    same.return_number = s.return_number;
    same.number_of_returns = s.number_of_returns;
    same.classification = s.classification;
    same.user_data = s.user_data;
    LasRecordBlock fresh;
    writer.encode(same, fresh);
    ASSERT_EQ(reused.count, 1u);
    ASSERT_EQ(fresh.count, 1u);
    const std::size_t size = writer.header().point_record_length;
    EXPECT_TRUE(std::equal(fresh.bytes.begin(),
                           fresh.bytes.begin() + static_cast<std::ptrdiff_t>(size),
                           reused.bytes.begin()));
    EXPECT_EQ(reused.by_return, fresh.by_return);
    EXPECT_EQ(std::vector<std::int32_t>(reused.lo, reused.lo + 3),
              std::vector<std::int32_t>(fresh.lo, fresh.lo + 3));
}

/// n points at random places over the extent {634000, 4849000, 0}-{636000, 4851000, 200}, with
/// random scan angles and GPS times 10 us apart (the other fields their defaults).
std::vector<LasSimplePoint> random_points(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<LasSimplePoint> points(n);
    for (std::size_t i = 0; i < points.size(); ++i) {
        LasSimplePoint& p = points[i];
        p.x = 634000 + 2000 * u(rng);
        p.y = 4849000 + 2000 * u(rng);
        p.z = 200 * u(rng);
        p.gps_time = static_cast<double>(i) * 1e-5;
        p.scan_angle_deg = static_cast<float>(60 * u(rng) - 30);
    }
    return points;
}

TEST_F(LasWriterTest, EncodePointsGivesWhatEncodingOneByOneGives) {
    LasWriterConfig config = las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200});
    config.point_format = 7;
    const LasWriter writer(config);
    std::vector<LasSimplePoint> points = random_points(300, 11);
    for (std::size_t i = 0; i < points.size(); ++i) {
        LasSimplePoint& p = points[i];
        p.intensity = static_cast<std::uint16_t>(i * 7);
        p.return_number = static_cast<std::uint8_t>(i % 4);  // 0: counted in no return
        p.number_of_returns = 3;
        p.red = static_cast<std::uint16_t>(i);
        p.scanner_channel = static_cast<std::uint8_t>(i % 4);
    }
    // Into an empty block, then after points already there (its bounds kept).
    const std::span<const LasSimplePoint> all(points);
    LasRecordBlock one, batch;
    for (const LasSimplePoint& p : points) {
        writer.encode(p, one);
    }
    writer.encode_points(all.first(100), batch);
    writer.encode_points(all.subspan(100, 0), batch);
    writer.encode_points(all.subspan(100), batch);
    ASSERT_EQ(batch.count, one.count);
    const std::size_t size = points.size() * writer.header().point_record_length;
    EXPECT_TRUE(std::equal(one.bytes.begin(), one.bytes.begin() + static_cast<std::ptrdiff_t>(size),
                           batch.bytes.begin()));
    EXPECT_EQ(batch.by_return, one.by_return);
    EXPECT_EQ(std::vector<std::int32_t>(batch.lo, batch.lo + 3),
              std::vector<std::int32_t>(one.lo, one.lo + 3));
    EXPECT_EQ(std::vector<std::int32_t>(batch.hi, batch.hi + 3),
              std::vector<std::int32_t>(one.hi, one.hi + 3));
}

// encode_points() runs a loop of its own for format 6 without extra bytes (the bare 30-byte
// record) and the general one otherwise: each gives the bytes, bounds and return counts of
// encoding the points one by one (which never takes the bare loop), and rejects the same points.
TEST_F(LasWriterTest, EncodePointsBareOrNotGivesWhatEncodingOneByOneGives) {
    std::vector<LasSimplePoint> points = random_points(257, 12);
    for (std::size_t i = 0; i < points.size(); ++i) {
        LasSimplePoint& p = points[i];
        p.intensity = static_cast<std::uint16_t>(i * 13);
        p.point_source_id = static_cast<std::uint16_t>(i * 3);
        p.return_number = static_cast<std::uint8_t>(i % 5);  // 0: counted in no return
        p.number_of_returns = 4;
        p.classification = static_cast<std::uint8_t>(i % 7);
        p.user_data = static_cast<std::uint8_t>(i);
        p.red = p.green = p.blue = p.nir = static_cast<std::uint16_t>(i + 1);
        p.scanner_channel = static_cast<std::uint8_t>(i % 4);
    }
    for (const auto& [format, extra] :
         {std::pair{6, 0}, std::pair{6, 4}, std::pair{7, 0}, std::pair{8, 0}}) {
        SCOPED_TRACE("format " + std::to_string(format) + ", " + std::to_string(extra) +
                     " extra bytes");
        LasWriterConfig config =
            las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200});
        config.point_format = format;
        config.extra_bytes_per_point = static_cast<std::uint16_t>(extra);
        const LasWriter writer(config);
        LasRecordBlock one, batch;
        for (const LasSimplePoint& p : points) {
            writer.encode(p, one);
        }
        // Stale bytes in the block's reused space: every byte of each record is written.
        batch.bytes.assign(points.size() * writer.header().point_record_length, 0xA5);
        const std::span<const LasSimplePoint> all(points);
        writer.encode_points(all.first(100), batch);
        writer.encode_points(all.subspan(100), batch);
        ASSERT_EQ(batch.count, one.count);
        const auto size =
            static_cast<std::ptrdiff_t>(points.size() * writer.header().point_record_length);
        EXPECT_TRUE(std::equal(one.bytes.begin(), one.bytes.begin() + size, batch.bytes.begin()));
        EXPECT_EQ(batch.by_return, one.by_return);
        for (std::size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(batch.lo[k], one.lo[k]);
            EXPECT_EQ(batch.hi[k], one.hi[k]);
        }
        std::vector<LasSimplePoint> bad(points.begin(), points.begin() + 3);
        bad[2].scanner_channel = 4;
        LasRecordBlock rejected;
        try {
            writer.encode_points(std::span<const LasSimplePoint>(bad), rejected);
            ADD_FAILURE() << "expected OutputError";
        } catch (const OutputError& e) {
            EXPECT_NE(std::string(e.what()).find("point 2: scanner channel 4 exceeds 3"),
                      std::string::npos)
                << e.what();
        }
    }
}

/// What encoding `points` one by one into an empty block gives, or the message of the first
/// point it rejects.
std::string encode_one_by_one(const LasWriter& writer, std::span<const LasSimplePoint> points,
                              LasRecordBlock& block) {
    try {
        for (const LasSimplePoint& p : points) {
            writer.encode(p, block);
        }
    } catch (const OutputError& e) {
        return e.what();
    }
    return {};
}

// The bare loop (format 6, which runs x, y and z in the lanes of one vector where the CPU has
// AVX2) rounds halves away from zero in every lane, keeps -0.5 < f < 0.5 truncated, takes
// coordinates up to the int32 limits, and names the same point and problem as the one-by-one
// encoding when a point in the middle of a block does not fit.
TEST_F(LasWriterTest, EncodePointsBareRoundsAndRejectsAsOneByOne) {
    LasWriterConfig config;
    config.scale = {0.25, 0.25, 0.25};  // steps = 4 x, exactly
    const LasWriter writer(config);
    const double steps[] = {0.5,
                            -0.5,
                            1.5,
                            -1.5,
                            2.5,
                            -2.5,
                            0.0,
                            -0.0,
                            0.49999999999999994,
                            -0.49999999999999994,
                            3.49,
                            -3.51,
                            2147483647.4,
                            -2147483648.4,
                            1e6 + 0.5,
                            -7.0};
    constexpr std::size_t n = std::size(steps);
    std::vector<LasSimplePoint> points = random_points(3 * n, 13);
    for (std::size_t i = 0; i < points.size(); ++i) {
        points[i].x = steps[i % n] / 4;
        points[i].y = steps[(i + 1) % n] / 4;
        points[i].z = steps[(i + 5) % n] / 4;
        points[i].return_number = static_cast<std::uint8_t>(i % 3);
        points[i].number_of_returns = 2;
    }
    LasRecordBlock one, batch;
    ASSERT_EQ(encode_one_by_one(writer, points, one), "");
    writer.encode_points(std::span<const LasSimplePoint>(points), batch);
    ASSERT_EQ(batch.count, one.count);
    EXPECT_TRUE(std::equal(one.bytes.begin(), one.bytes.begin() + 30 * 3 * n, batch.bytes.begin()));
    EXPECT_EQ(batch.by_return, one.by_return);
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(batch.lo[k], one.lo[k]) << k;
        EXPECT_EQ(batch.hi[k], one.hi[k]) << k;
    }
    EXPECT_EQ(one.lo[0], -2147483648);
    EXPECT_EQ(one.hi[0], 2147483647);
    const auto spoil =
        std::vector<void (*)(LasSimplePoint&)>{[](LasSimplePoint& p) { p.x = 2147483647.5 / 4; },
                                               [](LasSimplePoint& p) { p.y = -2147483648.5 / 4; },
                                               [](LasSimplePoint& p) { p.z = std::nan(""); },
                                               [](LasSimplePoint& p) { p.number_of_returns = 16; },
                                               [](LasSimplePoint& p) { p.scan_angle_deg = 180.5f; },
                                               [](LasSimplePoint& p) { p.scanner_channel = 4; }};
    for (std::size_t s = 0; s < spoil.size(); ++s) {
        std::vector<LasSimplePoint> bad(points.begin(), points.begin() + 9);
        spoil[s](bad[5]);
        LasRecordBlock expected;
        const std::string why = encode_one_by_one(writer, bad, expected);
        ASSERT_NE(why.find("point 5: "), std::string::npos) << s << ": " << why;
        LasRecordBlock rejected;
        try {
            writer.encode_points(std::span<const LasSimplePoint>(bad), rejected);
            ADD_FAILURE() << s << ": expected OutputError";
        } catch (const OutputError& e) {
            EXPECT_EQ(std::string(e.what()), why);
        }
    }
}

TEST_F(LasWriterTest, BlockEncodingRejectsBadPointsWithoutHarmingTheWriter) {
    LasWriter writer(dir_ / "x.las", {});
    LasRecordBlock block;
    LasPoint good;
    good.return_number = good.number_of_returns = 1;
    writer.encode(good, block);
    LasPoint bad = good;
    bad.y = 1e7;
    try {
        writer.encode(bad, block);
        FAIL() << "expected OutputError";
    } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find("point 1: y = 10000000"), std::string::npos)
            << e.what();
    }
    writer.write_block(block);
    writer.close();
    LasReader reader(dir_ / "x.las");
    EXPECT_EQ(reader.header().point_count, 1u);
    EXPECT_EQ(reader.header().points_by_return[0], 1u);
}

TEST_F(LasWriterTest, UnclosedWriterLeavesNothing) {
    const auto points = make_points(1000, 6);
    {
        LasWriter writer(dir_ / "abandoned.las",
                         las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200}));
        writer.write(points);
    }
    EXPECT_EQ(entry_count(dir_.path()), 0u);
}

TEST_F(LasWriterTest, InvalidConfigListsEveryProblem) {
    LasWriterConfig config;
    config.point_format = 3;
    config.scale.y = 0.0;
    config.system_identifier = std::string(33, 'a');
    config.vlrs.push_back(
        {"an-overlong-user-id", 1, "", std::vector<std::uint8_t>(70000), false, 0});
    try {
        LasWriter writer(dir_ / "x.las", config);
        FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
        const std::string message = e.what();
        for (const char* fragment : {"point_format: 3", "scale.y", "system_identifier",
                                     "user_id is longer", "mark it extended"}) {
            EXPECT_NE(message.find(fragment), std::string::npos) << fragment << "\n" << message;
        }
    }
    EXPECT_EQ(entry_count(dir_.path()), 0u);
}

TEST(LasConfigForExtent, CentresTheOffsetAndCoarsensTheScaleOnlyWhenNeeded) {
    const auto small = las_config_for_extent({500000.2, 5000000.7, -10}, {501000, 5001000, 90});
    EXPECT_EQ(small.offset, Vec3d(500500, 5000500, 40));
    EXPECT_EQ(small.scale, Vec3d(0.001, 0.001, 0.001));
    // 10 000 km at 1 mm needs 5e9 steps each side: 2 mm (2.5e9) is still too fine, 5 mm fits.
    const auto huge = las_config_for_extent({-5e6, 0, 0}, {5e6, 1, 1});
    EXPECT_DOUBLE_EQ(huge.scale.x, 0.005);
    EXPECT_EQ(huge.scale.y, 0.001);
    EXPECT_THROW(static_cast<void>(las_config_for_extent({1, 0, 0}, {0, 1, 1})), ConfigError);
    EXPECT_THROW(static_cast<void>(las_config_for_extent({0, 0, 0}, {1, 1, 1}, 0.0)), ConfigError);
    EXPECT_THROW(static_cast<void>(las_config_for_extent(Aabb{})), ConfigError);
    Aabb box;
    box.extend(Vec3f(-1, -2, -3));
    box.extend(Vec3f(3, 2, 1));
    EXPECT_EQ(las_config_for_extent(box, 0.01).offset, Vec3d(1, 0, -1));
}

TEST_F(LasWriterTest, ExtentConfigFitsPointsAtTheCorners) {
    const Vec3d lo{-5e6, -3e6, -1000}, hi{5e6, 3e6, 9000};
    const LasWriterConfig config = las_config_for_extent(lo, hi);
    std::vector<LasPoint> points(2);
    points[0].x = lo.x, points[0].y = lo.y, points[0].z = lo.z;
    points[1].x = hi.x, points[1].y = hi.y, points[1].z = hi.z;
    LasWriter writer(dir_ / "corners.las", config);
    writer.write(points);
    writer.close();
    const auto back = read_las_points(dir_ / "corners.las");
    ASSERT_EQ(back.size(), 2u);
    EXPECT_NEAR(back[0].x, lo.x, 0.5 * config.scale.x);
    EXPECT_NEAR(back[1].y, hi.y, 0.5 * config.scale.y);
}

// --- reader checks on broken files made from a valid one -----------------------------------

/// A small valid LAS 1.4 file (format 6, 10 points, one VLR) as bytes.
std::string valid_las_bytes(const fs::path& dir) {
    LasWriterConfig config = las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200});
    config.vlrs.push_back({"test", 7, "seven", {1, 2, 3}, false, 0});
    const fs::path path = dir / "valid.las";
    LasWriter writer(path, config);
    writer.write(make_points(10, 6));
    writer.close();
    std::string bytes = test::read_file(path);
    fs::remove(path);
    return bytes;
}

template <typename T>
void patch(std::string& bytes, std::size_t offset, T value) {
    std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

class LasReaderBroken : public test::TempDirTest {
  protected:
    void SetUp() override { good_ = valid_las_bytes(dir_.path()); }
    void expect_error(const std::string& bytes, const std::string& fragment) {
        const fs::path path = write("broken.las", bytes);
        test::expect_input_error([](const fs::path& p) { return LasReader(p).header(); }, path,
                                 fragment);
    }
    std::string good_;
};

TEST_F(LasReaderBroken, ValidFileReads) {
    const auto points = read_las_points(write("ok.las", good_));
    EXPECT_EQ(points.size(), 10u);
}

TEST_F(LasReaderBroken, BadSignature) {
    std::string b = good_;
    b[0] = 'X';
    expect_error(b, "bad file signature");
    expect_error("LAS", "too short");
    expect_error(good_.substr(0, 100), "shorter than the 227-byte LAS header");
}

TEST_F(LasReaderBroken, UnsupportedVersion) {
    std::string b = good_;
    b[24] = 2;
    b[25] = 0;
    expect_error(b, "unsupported LAS version 2.0");
    b[24] = 1;
    b[25] = 5;
    expect_error(b, "unsupported LAS version 1.5");
}

TEST_F(LasReaderBroken, UnknownOrCompressedPointFormat) {
    std::string b = good_;
    b[104] = 11;
    expect_error(b, "unknown point data record format 11");
    b[104] = static_cast<char>(6 | 0x80);
    expect_error(b, "marks a LAZ file, but it has no LASzip VLR");
}

TEST_F(LasReaderBroken, LaszipVlr) {
    std::string b = good_;
    std::memset(b.data() + 375 + 2, 0, 16);
    std::memcpy(b.data() + 375 + 2, "laszip encoded", 14);
    patch<std::uint16_t>(b, 375 + 18, 22204);
    b[104] = static_cast<char>(6 | 0x80);
    expect_error(b, "VLR 1: LASzip VLR:");
}

TEST_F(LasReaderBroken, RecordLengthTooSmall) {
    std::string b = good_;
    patch<std::uint16_t>(b, 105, 29);
    expect_error(b, "point record length 29 is smaller than the 30 bytes of point format 6");
}

TEST_F(LasReaderBroken, PointDataInsideHeader) {
    std::string b = good_;
    patch<std::uint32_t>(b, 96, 120);
    expect_error(b, "header: point data offset 120 is inside the header (size 375)");
}

TEST_F(LasReaderBroken, HeaderTooSmallForVersion) {
    std::string b = good_;
    patch<std::uint16_t>(b, 94, 227);
    expect_error(b, "header size 227 is smaller than the 375 bytes of LAS 1.4");
}

TEST_F(LasReaderBroken, VlrsRunIntoThePoints) {
    std::string b = good_;
    patch<std::uint32_t>(b, 100, 2);
    expect_error(b, "VLR 2 of 2: its header at byte 432 runs past the start of the point data");
    b = good_;
    patch<std::uint16_t>(b, 375 + 20, 4);
    expect_error(b, "VLR 1 of 1 (test/7): its 4 bytes of data");
}

TEST_F(LasReaderBroken, TruncatedPointsNameBothCounts) {
    expect_error(good_.substr(0, good_.size() - 1),
                 "point data: header says 10 points but the file holds only 9");
    std::string b = good_;
    patch<std::uint64_t>(b, 247, ~std::uint64_t{0});  // no overflow on absurd counts
    expect_error(b, "header says 18446744073709551615 points");
}

TEST_F(LasReaderBroken, PointDataOffsetPastTheEndIsRefusedEvenWithNoPoints) {
    std::string b = good_;
    patch<std::uint32_t>(b, 107, 0);  // legacy count
    patch<std::uint64_t>(b, 247, 0);  // 64-bit count
    patch<std::uint32_t>(b, 96, static_cast<std::uint32_t>(good_.size() + 1000));
    expect_error(b, "point data offset " + std::to_string(good_.size() + 1000) +
                        " lies past the end of the file (" + std::to_string(good_.size()) +
                        " bytes)");
    // Right at the end, with no points, is an empty file's layout and reads.
    patch<std::uint32_t>(b, 96, static_cast<std::uint32_t>(good_.size()));
    EXPECT_EQ(LasReader(write("end.las", b)).header().point_count, 0u);
}

TEST_F(LasReaderBroken, EvlrOutsideTheFile) {
    std::string b = good_ + std::string(20, 'e');
    patch<std::uint32_t>(b, 243, 1);
    patch<std::uint64_t>(b, 235, good_.size());
    expect_error(b, "EVLR 1 of 1: its header at byte");
    patch<std::uint64_t>(b, 235, 400);
    expect_error(b, "first EVLR at byte 400 starts before the end of the point data");
}

TEST_F(LasReaderBroken, ExtraHeaderBytesAndUserBytesAreSkipped) {
    // 16 extra header bytes, and 8 bytes between the VLRs and the points.
    std::string b = good_.substr(0, 375) + std::string(16, 'h') + good_.substr(375, 54 + 3) +
                    std::string(8, 'u') + good_.substr(375 + 57);
    patch<std::uint16_t>(b, 94, 375 + 16);
    patch<std::uint32_t>(b, 96, 375 + 16 + 57 + 8);
    const fs::path path = write("padded.las", b);
    LasReader reader(path);
    ASSERT_EQ(reader.vlrs().size(), 1u);
    EXPECT_EQ(reader.vlrs()[0].data, (std::vector<std::uint8_t>{1, 2, 3}));
    const auto want = read_las_points(write("ok.las", good_));
    std::vector<LasPoint> got(20);
    ASSERT_EQ(reader.read(got), 10u);
    for (std::size_t i = 0; i < 10; ++i) {
        EXPECT_EQ(got[i], want[i]) << i;
    }
}

// --- damaged files: refused, or loaded with only what the damage can reach changed ------------

/// Everything a reader returns for a LAS file.
struct LasContents {
    LasHeader header;
    std::vector<LasVlr> vlrs;
    std::vector<LasPoint> points;
};

LasContents load_las(const fs::path& path) {
    LasReader reader(path);
    LasContents c{reader.header(), reader.vlrs(), {}};
    c.points.resize(static_cast<std::size_t>(c.header.point_count));
    c.points.resize(reader.read(c.points));
    return c;
}

/// The LAS 1.4 header's fields, [begin, end) bytes each (ASPRS LAS 1.4 R15, table 3).
struct LasHeaderField {
    std::size_t begin, end;
    const char* name;
};
constexpr LasHeaderField kLasHeaderFields[] = {{0, 4, "signature"},
                                               {4, 6, "file_source_id"},
                                               {6, 8, "global_encoding"},
                                               {8, 24, "project_guid"},
                                               {24, 25, "version_major"},
                                               {25, 26, "version_minor"},
                                               {26, 58, "system_identifier"},
                                               {58, 90, "generating_software"},
                                               {90, 92, "creation_day"},
                                               {92, 94, "creation_year"},
                                               {94, 96, "header_size"},
                                               {96, 100, "offset_to_point_data"},
                                               {100, 104, "number_of_vlrs"},
                                               {104, 105, "point_format"},
                                               {105, 107, "record_length"},
                                               {107, 111, "legacy_point_count"},
                                               {111, 131, "legacy_by_return"},
                                               {131, 139, "scale.x"},
                                               {139, 147, "scale.y"},
                                               {147, 155, "scale.z"},
                                               {155, 163, "offset.x"},
                                               {163, 171, "offset.y"},
                                               {171, 179, "offset.z"},
                                               {179, 187, "max.x"},
                                               {187, 195, "min.x"},
                                               {195, 203, "max.y"},
                                               {203, 211, "min.y"},
                                               {211, 219, "max.z"},
                                               {219, 227, "min.z"},
                                               {227, 235, "start_of_waveform"},
                                               {235, 243, "start_of_first_evlr"},
                                               {243, 247, "number_of_evlrs"},
                                               {247, 255, "point_count"},
                                               {255, 375, "points_by_return"}};

/// The names (as in kLasHeaderFields) of the header fields in which `a` and `b` differ.
std::set<std::string> header_differences(const LasHeader& a, const LasHeader& b) {
    std::set<std::string> d;
    const auto note = [&d](const std::string& name, bool same) {
        if (!same) {
            d.insert(name);
        }
    };
    note("file_source_id", a.file_source_id == b.file_source_id);
    note("global_encoding", a.global_encoding == b.global_encoding);
    note("project_guid", a.project_guid == b.project_guid);
    note("version_major", a.version_major == b.version_major);
    note("version_minor", a.version_minor == b.version_minor);
    note("system_identifier", a.system_identifier == b.system_identifier);
    note("generating_software", a.generating_software == b.generating_software);
    note("creation_day", a.creation_day_of_year == b.creation_day_of_year);
    note("creation_year", a.creation_year == b.creation_year);
    note("header_size", a.header_size == b.header_size);
    note("offset_to_point_data", a.offset_to_point_data == b.offset_to_point_data);
    note("number_of_vlrs", a.number_of_vlrs == b.number_of_vlrs);
    note("point_format", a.point_format == b.point_format);
    note("record_length", a.point_record_length == b.point_record_length);
    note("legacy_point_count", a.legacy_point_count == b.legacy_point_count);
    note("legacy_by_return", a.legacy_points_by_return == b.legacy_points_by_return);
    for (std::size_t k = 0; k < 3; ++k) {
        const std::string axis(1, "xyz"[k]);
        // Bit patterns, so that a NaN read back from the same bytes counts as the same.
        note("scale." + axis,
             std::bit_cast<std::uint64_t>(a.scale[k]) == std::bit_cast<std::uint64_t>(b.scale[k]));
        note("offset." + axis, std::bit_cast<std::uint64_t>(a.offset[k]) ==
                                   std::bit_cast<std::uint64_t>(b.offset[k]));
        note("min." + axis,
             std::bit_cast<std::uint64_t>(a.min[k]) == std::bit_cast<std::uint64_t>(b.min[k]));
        note("max." + axis,
             std::bit_cast<std::uint64_t>(a.max[k]) == std::bit_cast<std::uint64_t>(b.max[k]));
    }
    note("start_of_waveform", a.start_of_waveform_data == b.start_of_waveform_data);
    note("start_of_first_evlr", a.start_of_first_evlr == b.start_of_first_evlr);
    note("number_of_evlrs", a.number_of_evlrs == b.number_of_evlrs);
    note("point_count", a.point_count == b.point_count);
    note("points_by_return", a.points_by_return == b.points_by_return);
    return d;
}

bool same_vlrs(const std::vector<LasVlr>& a, const std::vector<LasVlr>& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const auto& x, const auto& y) {
        return x.user_id == y.user_id && x.record_id == y.record_id &&
               x.description == y.description && x.data == y.data && x.extended == y.extended &&
               x.length == y.length;
    });
}

/// How the points of a damaged file may differ from the original's.
enum class PointsMay {
    stay,               ///< all there, all equal
    change_one,         ///< all there, all equal but point `which`
    change_coordinate,  ///< all there, equal but for coordinate `which` (0-2) of any point
    shrink,             ///< the first n of the original, n = the header's point count
    change_all,         ///< all there (the count is not touched), any values
};

/// What a load of a file with one damaged byte may legitimately return.
struct LasAllowance {
    std::set<std::string> header_fields;  ///< header fields that may differ
    bool vlrs = false;                    ///< whether the VLRs may differ
    PointsMay points = PointsMay::stay;
    std::size_t which = 0;
};

/// What a flip at byte `offset` of `want` (one file, no EVLRs) can reach: a header field and
/// what the reader derives from it, a VLR, or the one point record the byte is in.
LasAllowance las_allowance(std::size_t offset, const LasContents& want) {
    LasAllowance may;
    const LasHeader& h = want.header;
    if (offset >= h.offset_to_point_data) {
        may.points = PointsMay::change_one;
        may.which = (offset - h.offset_to_point_data) / h.point_record_length;
        return may;
    }
    if (offset >= h.header_size) {
        may.vlrs = true;
        return may;
    }
    const auto* field = std::find_if(std::begin(kLasHeaderFields), std::end(kLasHeaderFields),
                                     [&](const auto& f) { return offset < f.end; });
    const std::string name = field->name;
    may.header_fields.insert(name);
    if (name.starts_with("scale.") || name.starts_with("offset.")) {
        may.points = PointsMay::change_coordinate;  // x, y or z of every point
        may.which = static_cast<std::size_t>(name.back() - 'x');
    } else if (name == "version_minor") {
        // Before 1.4 the count comes from the legacy field (0 in formats 6-10).
        may.header_fields.insert({"point_count", "points_by_return", "start_of_waveform",
                                  "start_of_first_evlr", "number_of_evlrs"});
        may.points = PointsMay::shrink;
    } else if (name == "point_count") {
        may.points = PointsMay::shrink;
    } else if (name == "offset_to_point_data" || name == "point_format" ||
               name == "record_length") {
        may.vlrs = name == "offset_to_point_data";
        may.points = PointsMay::change_all;
    } else if (name == "header_size" || name == "number_of_vlrs" || name == "number_of_evlrs") {
        may.vlrs = true;
    }
    return may;
}

template <typename Point>
auto& coordinate(Point& p, std::size_t k) {
    return k == 0 ? p.x : (k == 1 ? p.y : p.z);
}

/// Fails the test unless `got` differs from `want` only as `may` allows.
void expect_within(const LasContents& got, const LasContents& want, const LasAllowance& may) {
    for (const auto& name : header_differences(got.header, want.header)) {
        EXPECT_TRUE(may.header_fields.contains(name)) << "header field " << name << " changed";
    }
    EXPECT_TRUE(may.vlrs || same_vlrs(got.vlrs, want.vlrs)) << "the VLRs changed";
    // Never fewer points than the reader's own header says.
    ASSERT_EQ(got.points.size(), got.header.point_count);
    if (may.points == PointsMay::shrink) {
        ASSERT_LE(got.points.size(), want.points.size());
    } else {
        ASSERT_EQ(got.points.size(), want.points.size());
    }
    if (may.points == PointsMay::change_all) {
        return;
    }
    for (std::size_t i = 0; i < got.points.size(); ++i) {
        LasPoint p = got.points[i];
        if (may.points == PointsMay::change_coordinate) {
            coordinate(p, may.which) = coordinate(want.points[i], may.which);
        }
        if (may.points != PointsMay::change_one || i != may.which) {
            EXPECT_EQ(p, want.points[i]) << "point " << i << " changed";
        }
    }
}

TEST_F(LasReaderBroken, EveryTruncationIsRefusedAndByteFlipsChangeOnlyWhatTheyHit) {
    const fs::path path = dir_ / "fuzz.las";
    const auto load = [&](const std::string& bytes) { return load_las(write_file(path, bytes)); };
    const LasContents want = load(good_);
    ASSERT_EQ(want.points.size(), 10u);
    // Every byte of a LAS file without EVLRs is header, VLRs or points: no cut may load.
    test::check_every_truncation(good_, load, [](const LasContents& got, std::size_t) {
        ADD_FAILURE() << "a truncated file loaded, with " << got.points.size() << " points";
    });
    std::mt19937 rng(7);
    test::check_random_byte_flips(good_, rng, 300, load,
                                  [&](const LasContents& got, const test::ByteFlip& flip) {
                                      expect_within(got, want, las_allowance(flip.offset, want));
                                  });
}

TEST_F(LasReaderBroken, EveryTruncationOfAFileWithAnEvlrIsRefused) {
    LasWriterConfig config = las_config_for_extent({634000, 4849000, 0}, {636000, 4851000, 200});
    config.point_format = 7;
    config.vlrs.push_back({"test", 8, "after the points", {9, 8, 7, 6}, true, 0});
    {
        LasWriter writer(dir_ / "evlr.las", config);
        writer.write(make_points(4, 7));
        writer.close();
    }
    const std::string bytes = test::read_file(dir_ / "evlr.las");
    ASSERT_EQ(load_las(dir_ / "evlr.las").vlrs.size(), 1u);
    const fs::path path = dir_ / "cut.las";
    test::check_every_truncation(
        bytes, [&](const std::string& b) { return load_las(write_file(path, b)); },
        [](const LasContents&, std::size_t) { ADD_FAILURE() << "a truncated file loaded"; });
}

TEST_F(LasReaderBroken, MissingFileAndDirectory) {
    test::expect_input_error([](const fs::path& p) { return LasReader(p).header(); },
                             dir_ / "missing.las", "cannot open");
    test::expect_input_error([](const fs::path& p) { return LasReader(p).header(); }, dir_.path(),
                             "is a directory");
}

}  // namespace
}  // namespace beamtrace
