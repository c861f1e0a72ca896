// Point-wise chunks (compressor 1 and 2, items of version 1 and 2) against real LAZ files and
// their LAS twins, and the version-2 encoders by round trip and against LASzip's own bytes.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <random>
#include <string_view>
#include <utility>
#include <vector>

#include "laz/laz_items.hpp"
#include "laz/laz_test_file.hpp"
#include "laz/pointwise_chunk.hpp"
#include "test_support.hpp"

namespace beamtrace::laz {
namespace {

/// Every record of a LAZ file, decoded chunk by chunk.
std::vector<std::uint8_t> decode_all(const test::LazTestFile& f) {
    const std::size_t length = f.las.record_length;
    std::vector<std::uint8_t> out(f.las.point_count * length);
    std::size_t done = 0;
    for (const test::LazChunk& c : f.chunks) {
        EXPECT_LE(c.begin + c.size, f.las.bytes.size());
        const std::span<const std::uint8_t> bytes(f.las.bytes.data() + c.begin, c.size);
        decode_pointwise_chunk(
            f.items, bytes, c.points,
            std::span<std::uint8_t>(out).subspan(done * length, c.points * length));
        done += c.points;
    }
    EXPECT_EQ(done, f.las.point_count);
    return out;
}

/// The bounds of the decoded x, y, z equal the header's minimum and maximum (or, not `exact`,
/// lie inside them).
void expect_header_bounds(const test::LasTestFile& f, const std::vector<std::uint8_t>& out,
                          bool exact = true) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
        const auto scale = test::get<double>(f.bytes, 131 + 8 * axis);
        const auto offset = test::get<double>(f.bytes, 155 + 8 * axis);
        const auto max = test::get<double>(f.bytes, 179 + 16 * axis);
        const auto min = test::get<double>(f.bytes, 187 + 16 * axis);
        double lo = 1e300;
        double hi = -1e300;
        for (std::size_t p = 0; p < f.point_count; ++p) {
            std::int32_t raw = 0;
            std::memcpy(&raw, out.data() + p * f.record_length + 4 * axis, 4);
            lo = std::min(lo, raw * scale + offset);
            hi = std::max(hi, raw * scale + offset);
        }
        if (exact) {
            EXPECT_NEAR(lo, min, 0.5 * scale) << "axis " << axis;
            EXPECT_NEAR(hi, max, 0.5 * scale) << "axis " << axis;
        } else {
            EXPECT_GE(lo, min - 0.5 * scale) << "axis " << axis;
            EXPECT_LE(hi, max + 0.5 * scale) << "axis " << axis;
        }
    }
}

/// Decodes `laz` and compares each record's first `compare` bytes (the whole record by
/// default) with the twin's. With `reprojected`, the file holds the twin's points in other
/// coordinates: bytes 0-11 (x, y, z) are not compared, but their bounds must be the header's.
void expect_twin(const std::string& laz, const std::string& las, std::size_t compare = 0,
                 bool reprojected = false) {
    const auto laz_path = beamtrace::test::shared_data(laz);
    const auto las_path = beamtrace::test::shared_data(las);
    BEAMTRACE_REQUIRE_FILE(laz_path);
    BEAMTRACE_REQUIRE_FILE(las_path);
    const test::LazTestFile f = test::read_laz_test_file(laz_path);
    const test::LasTestFile twin = test::read_las_test_file(las_path);
    ASSERT_EQ(f.las.point_count, twin.point_count);
    const std::size_t length = f.las.record_length;
    const std::size_t n = compare == 0 ? length : compare;
    const std::vector<std::uint8_t> out = decode_all(f);
    const std::size_t from = reprojected ? 12 : 0;
    if (reprojected) {
        expect_header_bounds(f.las, out);
    }
    for (std::size_t p = 0; p < twin.point_count; ++p) {
        const std::vector<std::uint8_t> got(out.begin() + p * length + from,
                                            out.begin() + p * length + n);
        const std::vector<std::uint8_t> want(twin.record(p) + from, twin.record(p) + n);
        ASSERT_EQ(got, want) << laz << ": record " << p << " of " << twin.point_count;
    }
}

TEST(LazPointwise, SimpleFormat3ChunkedV2) {
    expect_twin("las/laz/simple.laz", "las/las/simple.las");
}

TEST(LazPointwise, AutzenTrimFormat3ManyChunks) {
    expect_twin("las/laz/autzen_trim.laz", "las/las/autzen_trim.las");
}

TEST(LazPointwise, PointColorFormat2) {
    expect_twin("las/laz/point-color.las.laz", "las/las/point-color.las");
}

// laz-perf's raw sets hold simple.las's points in formats 0 and 1 (reprojected).
TEST(LazPointwise, Point10Format0) {
    expect_twin("las/laz/point10.las.laz", "las/las/simple.las", 20, true);
}
TEST(LazPointwise, PointTimeFormat1) {
    expect_twin("las/laz/point-time.las.laz", "las/las/simple.las", 28, true);
}

TEST(LazPointwise, Version1ItemsUnchunkedCompressor1) {
    expect_twin("las/edge/point-version-1-point-wise.laz",
                "las/las/point-version-1-point-wise.las");
}

TEST(LazPointwise, Version1ItemsOldCompressor) {
    expect_twin("las/edge/simple-laszip-compressor-version-1.2r0.laz", "las/las/simple.las");
}

TEST(LazPointwise, ExtraBytesFormat3) {
    expect_twin("las/laz/extra.laz", "las/formats/extrabytes.las");
}

/// The items of a version-2 point-wise file of LAS point format `format` (0-3) with `extra`
/// extra bytes.
std::vector<Item> items_v2(unsigned format, std::uint16_t extra = 0) {
    std::vector<Item> items{{ItemType::point10, 20, 2}};
    if (format == 1 || format == 3) {
        items.push_back({ItemType::gpstime11, 8, 2});
    }
    if (format == 2 || format == 3) {
        items.push_back({ItemType::rgb12, 6, 2});
    }
    if (extra != 0) {
        items.push_back({ItemType::byte, extra, 2});
    }
    return items;
}

/// Encodes `records` in chunks of `chunk` points and decodes them back.
std::vector<std::uint8_t> round_trip(const std::vector<Item>& items,
                                     const std::vector<std::uint8_t>& records, std::size_t chunk) {
    const std::size_t length = record_length(items);
    const std::size_t count = records.size() / length;
    std::vector<std::uint8_t> back(records.size());
    for (std::size_t first = 0; first < count; first += chunk) {
        const std::size_t n = std::min(chunk, count - first);
        std::vector<std::uint8_t> coded{0x55};  // the chunk starts after other bytes
        encode_pointwise_chunk(items, std::span(records).subspan(first * length, n * length), n,
                               coded);
        EXPECT_EQ(coded[0], 0x55);
        decode_pointwise_chunk(items, std::span(coded).subspan(1), n,
                               std::span(back).subspan(first * length, n * length));
    }
    return back;
}

// Our encoders write exactly LASzip's bytes: re-encoding the LAS twin of a LAZ file reproduces
// each of its chunks. fwf.laz (WAVEPACKET13) has no twin: its own decoded records serve.
TEST(LazPointwise, EncoderReproducesLaszipChunks) {
    for (const auto& [laz, las] : {std::pair{"las/laz/simple.laz", "las/las/simple.las"},
                                   std::pair{"las/laz/autzen_trim.laz", "las/las/autzen_trim.las"},
                                   std::pair{"las/laz/extra.laz", "las/formats/extrabytes.las"},
                                   std::pair{"las/laz/fwf.laz", ""}}) {
        const auto laz_path = beamtrace::test::shared_data(laz);
        BEAMTRACE_REQUIRE_FILE(laz_path);
        const test::LazTestFile f = test::read_laz_test_file(laz_path);
        std::vector<std::uint8_t> records;
        if (std::string_view(las).empty()) {
            records = decode_all(f);
        } else {
            const auto las_path = beamtrace::test::shared_data(las);
            BEAMTRACE_REQUIRE_FILE(las_path);
            const test::LasTestFile twin = test::read_las_test_file(las_path);
            records.assign(twin.record(0), twin.record(twin.point_count));
        }
        const std::size_t length = f.las.record_length;
        ASSERT_EQ(records.size(), f.las.point_count * length);
        std::size_t first = 0;
        for (const test::LazChunk& c : f.chunks) {
            std::vector<std::uint8_t> coded;
            encode_pointwise_chunk(f.items,
                                   std::span(records).subspan(first * length, c.points * length),
                                   c.points, coded);
            const std::vector<std::uint8_t> want(f.las.bytes.begin() + c.begin,
                                                 f.las.bytes.begin() + c.begin + c.size);
            EXPECT_EQ(coded, want) << laz << ": chunk from point " << first;
            first += c.points;
        }
    }
}

TEST(LazPointwise, EncoderRoundTripsEveryFormat) {
    const auto path = beamtrace::test::shared_data("las/las/autzen_trim.las");
    BEAMTRACE_REQUIRE_FILE(path);
    const test::LasTestFile las = test::read_las_test_file(path);
    for (unsigned format = 0; format < 4; ++format) {
        const std::vector<Item> items = items_v2(format, format == 2 ? 3 : 0);
        const std::size_t length = record_length(items);
        // Format `format` records made of the format-3 twin's fields (and 3 made-up extra bytes).
        std::vector<std::uint8_t> records;
        for (std::size_t p = 0; p < 30000; ++p) {
            const std::uint8_t* r = las.record(p);
            records.insert(records.end(), r, r + 20);
            if (format == 1 || format == 3) {
                records.insert(records.end(), r + 20, r + 28);
            }
            if (format == 2 || format == 3) {
                records.insert(records.end(), r + 28, r + 34);
            }
            if (format == 2) {
                for (std::uint8_t b :
                     {static_cast<std::uint8_t>(p), r[0], static_cast<std::uint8_t>(7)}) {
                    records.push_back(b);
                }
            }
        }
        ASSERT_EQ(records.size(), 30000 * length);
        EXPECT_EQ(round_trip(items, records, 7000), records) << "format " << format;
        const std::vector<std::uint8_t> head(records.begin(), records.begin() + 300 * length);
        EXPECT_EQ(round_trip(items, head, 1), head) << "format " << format;
    }
}

// Synthetic GPS times that exercise every branch of GPSTIME11: repeats, regular steps,
// multiples, negative steps, huge jumps and up to four interleaved sequences.
TEST(LazPointwise, GpsTimeSequencesRoundTrip) {
    std::mt19937 rng(5);
    std::vector<std::uint8_t> records;
    std::array<double, 5> sequence{1.0e5, 3.0e8, -2.0e3, 1.0e-3, 7.0e14};
    std::size_t current = 0;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::size_t p = 0; p < 40000; ++p) {
        std::array<std::uint8_t, 28> r{};
        const double roll = u(rng);
        if (roll < 0.02) {
            current = rng() % sequence.size();  // jump to another sequence
        } else if (roll < 0.2) {
            // unchanged
        } else if (roll < 0.7) {
            sequence[current] += 1.0e-5;
        } else if (roll < 0.8) {
            sequence[current] += 1.0e-5 * static_cast<double>(rng() % 700);
        } else if (roll < 0.9) {
            sequence[current] -= 1.0e-5 * static_cast<double>(rng() % 20);
        } else {
            sequence[current] += u(rng) * 1.0e3;
        }
        std::memcpy(r.data(), &p, 4);
        r[14] = static_cast<std::uint8_t>(rng());
        std::memcpy(r.data() + 20, &sequence[current], 8);
        records.insert(records.end(), r.begin(), r.end());
    }
    EXPECT_EQ(round_trip(items_v2(1), records, 50000), records);
}

TEST(LazPointwise, ExtremeValuesRoundTrip) {
    std::mt19937 rng(9);
    const std::vector<Item> items = items_v2(3, 5);
    std::vector<std::uint8_t> records(20000 * record_length(items));
    for (std::size_t i = 0; i < records.size(); ++i) {
        // Runs of constant bytes mixed with noise: every field sees both repeats and jumps.
        records[i] = (i / 997) % 3 == 0 ? static_cast<std::uint8_t>(rng())
                                        : static_cast<std::uint8_t>(i % 251 == 0 ? 0xFF : 0);
    }
    EXPECT_EQ(round_trip(items, records, 5000), records);
}

// Point format 4 records (POINT10, GPSTIME11, WAVEPACKET13) whose packet offsets repeat,
// follow one another, step by small and by huge amounts.
TEST(LazPointwise, WavePacketsRoundTrip) {
    const std::vector<Item> items{
        {ItemType::point10, 20, 2}, {ItemType::gpstime11, 8, 2}, {ItemType::wavepacket13, 29, 1}};
    std::mt19937 rng(4);
    std::vector<std::uint8_t> records;
    std::uint64_t offset = 60;
    std::uint32_t size = 256;
    for (std::uint32_t p = 0; p < 20000; ++p) {
        std::array<std::uint8_t, 57> r{};
        std::memcpy(r.data(), &p, 4);
        const double t = 1000.0 + p * 1.0e-5;
        std::memcpy(r.data() + 20, &t, 8);
        switch (rng() % 5) {
            case 0:
                break;
            case 1:
                offset += size;
                break;
            case 2:
                offset += rng() % 5000;
                break;
            case 3:
                offset -= rng() % 50;
                break;
            default:
                offset = (static_cast<std::uint64_t>(rng()) << 24) + rng();
        }
        size = rng() % 3 == 0 ? static_cast<std::uint32_t>(rng()) : size;
        r[28] = static_cast<std::uint8_t>(1 + rng() % 3);
        std::memcpy(r.data() + 29, &offset, 8);
        std::memcpy(r.data() + 37, &size, 4);
        for (std::size_t i = 41; i < 57; ++i) {
            r[i] = static_cast<std::uint8_t>(rng() % 4 == 0 ? rng() : 0x3F);
        }
        records.insert(records.end(), r.begin(), r.end());
    }
    EXPECT_EQ(round_trip(items, records, 6000), records);
}

TEST(LazPointwise, TruncatedOrCorruptChunksFailCleanly) {
    const auto path = beamtrace::test::shared_data("las/laz/simple.laz");
    BEAMTRACE_REQUIRE_FILE(path);
    const test::LazTestFile f = test::read_laz_test_file(path);
    const test::LazChunk& c = f.chunks.at(0);
    const std::size_t length = f.las.record_length;
    std::vector<std::uint8_t> out(c.points * length);
    for (std::size_t keep : {std::size_t{0}, std::size_t{10}, length + 2, c.size / 2}) {
        // An exact-size copy, so that ASan sees any read past it.
        const std::vector<std::uint8_t> cut(f.las.bytes.begin() + c.begin,
                                            f.las.bytes.begin() + c.begin + keep);
        EXPECT_THROW(decode_pointwise_chunk(f.items, cut, c.points, out), CorruptData) << keep;
    }
    std::mt19937 rng(1);
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<std::uint8_t> bad(f.las.bytes.begin() + c.begin,
                                      f.las.bytes.begin() + c.begin + c.size);
        for (int flips = 0; flips < 1 + trial % 5; ++flips) {
            bad[length + rng() % (bad.size() - length)] ^=
                static_cast<std::uint8_t>(1U << (rng() % 8));
        }
        bad.resize(bad.size() - rng() % 64);
        try {
            decode_pointwise_chunk(f.items, bad, c.points, out);
        } catch (const CorruptData&) {
        }
    }
    std::vector<Item> wrong = f.items;
    wrong[0].size = 19;
    EXPECT_THROW(decode_pointwise_chunk(wrong, {}, 1, out), CorruptData);
    wrong = f.items;
    wrong[1].version = 3;
    EXPECT_THROW(decode_pointwise_chunk(wrong, {}, 1, out), CorruptData);
    wrong = f.items;
    wrong[2].type = ItemType::point14;
    EXPECT_THROW(decode_pointwise_chunk(wrong, {}, 1, out), CorruptData);
}

// Damaged chunks of every item kind and version (and pure noise after the raw first record):
// decoded to something or refused with CorruptData, never a read or write out of bounds.
TEST(LazPointwise, DamagedChunksOfEveryItemKindFailCleanly) {
    std::mt19937 rng(2);
    for (const char* name :
         {"las/edge/point-version-1-point-wise.laz",
          "las/edge/simple-laszip-compressor-version-1.2r0.laz", "las/laz/extra.laz",
          "las/laz/fwf.laz", "las/laz/point-color.las.laz"}) {
        const auto path = beamtrace::test::shared_data(name);
        BEAMTRACE_REQUIRE_FILE(path);
        const test::LazTestFile f = test::read_laz_test_file(path);
        const test::LazChunk& c = f.chunks.at(0);
        const std::size_t length = f.las.record_length;
        const std::size_t points = std::min<std::size_t>(c.points, 3000);
        std::vector<std::uint8_t> out(points * length);
        for (int trial = 0; trial < 60; ++trial) {
            std::vector<std::uint8_t> bad(
                f.las.bytes.begin() + c.begin,
                f.las.bytes.begin() + c.begin + std::min<std::size_t>(c.size, 40000));
            for (std::size_t i = length; i < bad.size(); ++i) {
                if (trial % 4 == 0 || rng() % 2000 == 0) {
                    bad[i] = static_cast<std::uint8_t>(rng());
                }
            }
            bad.resize(length + rng() % (bad.size() - length));
            try {
                decode_pointwise_chunk(f.items, bad, points, out);
            } catch (const CorruptData&) {
            }
        }
    }
}

// A chunk decoded a batch at a time (as a reader does for compressor 1's single chunk, to
// bound its memory) gives the records of one whole decode.
TEST(LazPointwise, BatchedDecodeEqualsWholeChunk) {
    const auto path = beamtrace::test::shared_data("las/edge/point-version-1-point-wise.laz");
    BEAMTRACE_REQUIRE_FILE(path);
    const test::LazTestFile f = test::read_laz_test_file(path);
    const std::vector<std::uint8_t> whole = decode_all(f);
    const test::LazChunk& c = f.chunks.at(0);
    const std::span<const std::uint8_t> bytes(f.las.bytes.data() + c.begin, c.size);
    for (std::size_t batch : {std::size_t{1}, std::size_t{7}, std::size_t{1000}}) {
        PointwiseChunkDecoder decoder(f.items, bytes);
        const std::size_t length = decoder.record_length();
        std::vector<std::uint8_t> records;
        std::vector<std::uint8_t> buffer(batch * length);
        while (decoder.decoded() < c.points) {
            const std::size_t n = std::min(batch, c.points - decoder.decoded());
            decoder.decode(n, buffer);
            records.insert(records.end(), buffer.begin(),
                           buffer.begin() + static_cast<std::ptrdiff_t>(n * length));
        }
        EXPECT_EQ(records, whole) << "batches of " << batch;
        EXPECT_THROW(decoder.decode(2, std::span(buffer).first(length)), std::invalid_argument);
    }
}

// The point-wise files without a LAS twin: each decodes, and its points span exactly the
// header's bounding box (a decoder that goes astray leaves it at once). fwf.laz's header holds
// its tile's box, which its points lie inside.
TEST(LazPointwise, FilesWithoutTwinDecodeWithinTheirHeaderBounds) {
    for (const char* name :
         {"las/laz/32-1-472-150-76.laz", "las/laz/Megaplot.laz", "las/laz/MixedConifer.laz",
          "las/laz/Topography.laz", "las/laz/dbh.laz", "las/laz/point-time-1.4.las.laz",
          "las/laz/fwf.laz", "las/edge/no-points-1.3.laz"}) {
        const auto path = beamtrace::test::shared_data(name);
        BEAMTRACE_REQUIRE_FILE(path);
        SCOPED_TRACE(name);
        const test::LazTestFile f = test::read_laz_test_file(path);
        const std::vector<std::uint8_t> out = decode_all(f);
        if (f.las.point_count != 0) {
            expect_header_bounds(f.las, out, std::string_view(name) != "las/laz/fwf.laz");
        }
    }
}

// fwf.laz (point format 4): WAVEPACKET13 items whose packets follow one another in the
// external waveform file.
TEST(LazPointwise, WavePacketsAreContiguous) {
    const auto path = beamtrace::test::shared_data("las/laz/fwf.laz");
    BEAMTRACE_REQUIRE_FILE(path);
    const test::LazTestFile f = test::read_laz_test_file(path);
    const std::vector<std::uint8_t> out = decode_all(f);
    const std::size_t length = f.las.record_length;
    std::size_t contiguous = 0;
    for (std::size_t p = 1; p < f.las.point_count; ++p) {
        const std::uint8_t* a = out.data() + (p - 1) * length + 28;
        const std::uint8_t* b = out.data() + p * length + 28;
        std::uint64_t offset_a = 0;
        std::uint64_t offset_b = 0;
        std::uint32_t size_a = 0;
        std::memcpy(&offset_a, a + 1, 8);
        std::memcpy(&offset_b, b + 1, 8);
        std::memcpy(&size_a, a + 9, 4);
        EXPECT_NE(b[0], 0) << "descriptor index of point " << p;
        contiguous += (offset_b == offset_a + size_a || offset_b == offset_a) ? 1 : 0;
    }
    EXPECT_GT(contiguous, f.las.point_count * 9 / 10);
}

// The malformed LAZ files of the edge set: refused with CorruptData, or decoded, never a crash.
TEST(LazPointwise, BrokenEdgeFilesFailCleanly) {
    int refused = 0;
    for (const char* name : {"las/edge/broken_coder.laz", "las/edge/broken_size.laz",
                             "las/edge/broken_type.laz", "las/edge/broken_version.laz"}) {
        const auto path = beamtrace::test::shared_data(name);
        BEAMTRACE_REQUIRE_FILE(path);
        const test::LazTestFile f = test::read_laz_test_file(path);
        try {
            decode_all(f);
        } catch (const CorruptData& e) {
            EXPECT_NE(std::string(e.what()), "") << name;
            ++refused;
        }
    }
    EXPECT_GE(refused, 3);  // the wrong sizes, versions and types at least
}

}  // namespace
}  // namespace beamtrace::laz
