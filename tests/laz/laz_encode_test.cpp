// The LAZ writer's codec (laz/laz_encode.hpp) against LASzip's own bytes: the layered chunks of
// real LAZ files re-encoded from their decoded records, the LASzip VLR for their point format and
// their chunk tables; then round trips of synthetic records through every layered item.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "laz/laz_encode.hpp"
#include "laz/laz_items.hpp"
#include "laz/laz_test_file.hpp"
#include "test_support.hpp"

namespace beamtrace::laz {
namespace {

/// The bytes of chunk `c` of `f`.
std::span<const std::uint8_t> chunk_bytes(const test::LazTestFile& f, const test::LazChunk& c) {
    return std::span<const std::uint8_t>(f.las.bytes).subspan(c.begin, c.size);
}

/// Re-encodes the first `max_chunks` chunks of a layered file from their decoded records and
/// expects LASzip's bytes (reporting the first difference of each chunk that differs); returns
/// how many chunks were checked.
std::size_t reencode_chunks(const std::string& rel, std::size_t max_chunks) {
    const test::LazTestFile f = test::read_laz_test_file(beamtrace::test::shared_data(rel));
    EXPECT_EQ(f.compressor, 3) << rel;
    const std::size_t n = std::min(max_chunks, f.chunks.size());
    for (std::size_t k = 0; k < n; ++k) {
        const test::LazChunk& c = f.chunks[k];
        std::vector<std::uint8_t> records(c.points * f.las.record_length);
        decode_layered_chunk(f.items, chunk_bytes(f, c), c.points, records);
        std::vector<std::uint8_t> out;
        encode_layered_chunk(f.items, records, c.points, out);
        const std::span<const std::uint8_t> want = chunk_bytes(f, c);
        if (out.size() == want.size() && std::equal(out.begin(), out.end(), want.begin())) {
            continue;
        }
        const auto diff = std::mismatch(out.begin(), out.end(), want.begin(), want.end());
        ADD_FAILURE() << rel << " chunk " << k + 1 << " of " << f.chunks.size() << " (" << c.points
                      << " points): " << out.size() << " bytes, LASzip's " << want.size()
                      << ", first difference at byte " << (diff.first - out.begin());
    }
    return n;
}

TEST(LazEncode, LayeredChunksAreLaszipsBytes) {
    BEAMTRACE_REQUIRE_FILE(beamtrace::test::shared_data("las/laz"));
    // Every chunk of every layered sample: format 6 (LAStools 3.4r3; LASzip 2.2 with an EVLR),
    // 8 with BYTE14 (LASzip 2.2; 3.4r3, 14 chunks, 0.7 M points), COPC (variable chunks: format
    // 6, and 7 with RGB14), 10 with WAVEPACKET14 (3.4r4). (Those with a LAS twin hold one scanner
    // channel: the synthetic round trips below switch channels.)
    EXPECT_EQ(reencode_chunks("las/laz/las14_prf6.laz", 10), 1u);
    EXPECT_EQ(reencode_chunks("las/laz/1_4_w_evlr.laz", 10), 1u);
    EXPECT_EQ(reencode_chunks("las/laz/append-bug.laz", 10), 1u);
    EXPECT_EQ(reencode_chunks("las/laz/las_with_several_extra_byte_bloc.laz", 14), 14u);
    EXPECT_EQ(reencode_chunks("las/laz/lone-star.copc.laz", 40), 15u);
    EXPECT_EQ(reencode_chunks("las/laz/simple.copc.laz", 100), 65u);
    EXPECT_EQ(reencode_chunks("las/laz/fullwave.laz", 1), 1u);
}

/// The payload of the file's LASzip VLR.
std::vector<std::uint8_t> laszip_vlr_payload(const test::LasTestFile& f) {
    std::size_t at = f.header_size;
    for (std::size_t v = 0; v < f.vlr_count; ++v) {
        const std::string user(reinterpret_cast<const char*>(f.bytes.data() + at + 2));
        const auto id = test::get<std::uint16_t>(f.bytes, at + 18);
        const auto length = test::get<std::uint16_t>(f.bytes, at + 20);
        if (user == "laszip encoded" && id == 22204) {
            return {f.bytes.begin() + static_cast<std::ptrdiff_t>(at + 54),
                    f.bytes.begin() + static_cast<std::ptrdiff_t>(at + 54 + length)};
        }
        at += 54 + length;
    }
    ADD_FAILURE() << "no LASzip VLR";
    return {};
}

/// serialize_laz_vlr(laz_vlr_for(...)) for the file's format, record length and chunk size
/// against its VLR; `version`: whether the file's writer was LASzip 3.4r3 (else the three
/// version bytes are left out of the comparison).
void expect_laszip_vlr(const std::string& rel, bool version) {
    SCOPED_TRACE(rel);
    const test::LazTestFile f = test::read_laz_test_file(beamtrace::test::shared_data(rel));
    std::vector<std::uint8_t> want = laszip_vlr_payload(f.las);
    const LazVlr vlr =
        laz_vlr_for(static_cast<int>(f.las.point_format), f.las.record_length, f.chunk_size);
    std::vector<std::uint8_t> got = serialize_laz_vlr(vlr);
    ASSERT_EQ(got.size(), want.size());
    if (!version) {
        std::copy(got.begin() + 4, got.begin() + 8, want.begin() + 4);
    }
    EXPECT_EQ(got, want);
    const LazVlr parsed =
        parse_laz_vlr(got, static_cast<int>(f.las.point_format), f.las.record_length);
    EXPECT_EQ(parsed.items.size(), f.items.size());
    EXPECT_EQ(parsed.chunk_size, f.chunk_size);
}

TEST(LazEncode, VlrIsLaszipsForEveryFormat) {
    BEAMTRACE_REQUIRE_FILE(beamtrace::test::shared_data("las/laz"));
    // Written by LASzip 3.4r3: byte for byte.
    expect_laszip_vlr("las/laz/las14_prf6.laz", true);                        // 6
    expect_laszip_vlr("las/laz/las_with_several_extra_byte_bloc.laz", true);  // 8 + BYTE14
    expect_laszip_vlr("las/laz/lone-star.copc.laz", true);                    // 6, variable
    expect_laszip_vlr("las/laz/simple.copc.laz", true);                       // 7, variable
    expect_laszip_vlr("las/laz/dbh.laz", true);                               // 1 + BYTE
    expect_laszip_vlr("las/laz/fwf.laz", true);                               // 4
    expect_laszip_vlr("las/laz/simple.laz", true);                            // 3
    expect_laszip_vlr("las/laz/point-time-1.4.las.laz", true);                // 1
    // Other writers (LASzip 2.2, 3.1, 3.4r4): all but the version.
    expect_laszip_vlr("las/laz/fullwave.laz", false);         // 10
    expect_laszip_vlr("las/laz/1_4_w_evlr.laz", false);       // 6
    expect_laszip_vlr("las/laz/append-bug.laz", false);       // 8 + BYTE14
    expect_laszip_vlr("las/laz/point10.las.laz", false);      // 0
    expect_laszip_vlr("las/laz/point-color.las.laz", false);  // 2
    expect_laszip_vlr("las/laz/extra.laz", false);            // 3 + BYTE
}

TEST(LazEncode, VlrForRefusesImpossibleRecords) {
    EXPECT_THROW((void)laz_vlr_for(11, 40, 50000), std::invalid_argument);
    EXPECT_THROW((void)laz_vlr_for(-1, 40, 50000), std::invalid_argument);
    EXPECT_THROW((void)laz_vlr_for(6, 29, 50000), std::invalid_argument);
    EXPECT_THROW((void)laz_vlr_for(5, 62, 50000), std::invalid_argument);
    const LazVlr v = laz_vlr_for(10, 67 + 5, 1000);
    ASSERT_EQ(v.items.size(), 4u);
    EXPECT_EQ(v.items[3].type, ItemType::byte14);
    EXPECT_EQ(v.items[3].size, 5);
    EXPECT_EQ(v.compressor, Compressor::layered_chunked);
    EXPECT_EQ(v.chunk_size, 1000u);
}

/// encode_chunk_table of the file's chunks against the bytes at its table offset.
void expect_chunk_table(const std::string& rel) {
    SCOPED_TRACE(rel);
    const test::LazTestFile f = test::read_laz_test_file(beamtrace::test::shared_data(rel));
    std::vector<Chunk> chunks;
    for (const test::LazChunk& c : f.chunks) {
        chunks.push_back({c.begin, c.size, 0, c.points});
    }
    const std::vector<std::uint8_t> got = encode_chunk_table(chunks, f.chunk_size == 0xFFFFFFFFU);
    const auto at =
        static_cast<std::size_t>(test::get<std::int64_t>(f.las.bytes, f.las.point_offset));
    ASSERT_LE(at + got.size(), f.las.bytes.size());
    const std::vector<std::uint8_t> want(
        f.las.bytes.begin() + static_cast<std::ptrdiff_t>(at),
        f.las.bytes.begin() + static_cast<std::ptrdiff_t>(at + got.size()));
    EXPECT_EQ(got, want);
}

TEST(LazEncode, ChunkTablesAreLaszipsBytes) {
    BEAMTRACE_REQUIRE_FILE(beamtrace::test::shared_data("las/laz"));
    expect_chunk_table("las/laz/las14_prf6.laz");
    expect_chunk_table("las/laz/1_4_w_evlr.laz");
    expect_chunk_table("las/laz/las_with_several_extra_byte_bloc.laz");
    expect_chunk_table("las/laz/lone-star.copc.laz");  // variable: point counts too
    expect_chunk_table("las/laz/simple.copc.laz");
    expect_chunk_table("las/laz/autzen_trim.laz");  // point-wise, 3 chunks
    expect_chunk_table("las/laz/Megaplot.laz");
    EXPECT_EQ(encode_chunk_table({}, false), std::vector<std::uint8_t>(8, 0));
}

/// What the synthetic records vary.
struct Synthetic {
    int format = 6;
    std::size_t extra_bytes = 0;
    std::size_t points = 1000;
    std::uint32_t seed = 1;
    bool constant_attributes = false;  ///< classification, flags, user data, ... never change
};

template <typename T>
void put(std::uint8_t* p, T v) {
    std::memcpy(p, &v, sizeof v);
}

/// One channel's running state: its GPS time and position.
struct SyntheticChannel {
    double gps = 0.0;
    std::int32_t x = 0, y = 0, z = 0;
};

/// Seeded records of the 30-byte POINT14 core: channel switches, multiple returns, GPS time
/// repeats, regular steps, jumps (to far times and back) and the odd NaN.
void fill_point14(std::uint8_t* r, std::mt19937& rng, std::array<SyntheticChannel, 4>& ch,
                  unsigned& channel, const Synthetic& s) {
    auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    if (uniform(0, 9) == 0) {
        channel = static_cast<unsigned>(uniform(0, 3));
    }
    SyntheticChannel& c = ch[channel];
    const int gps_kind = uniform(0, 19);
    if (gps_kind < 12) {
        c.gps += 1e-5;
    } else if (gps_kind < 15) {
        c.gps += 1e-5 * uniform(2, 700);
    } else if (gps_kind == 15) {
        c.gps += uniform(0, 1) == 0 ? 1e7 : -1e7;  // another sequence
    } else if (gps_kind == 16) {
        c.gps -= 3e-5;
    } else if (gps_kind == 17 && s.seed % 2 == 0) {
        c.gps = std::numeric_limits<double>::quiet_NaN();
    } else if (std::isnan(c.gps)) {
        c.gps = 1000.0;
    }  // else: the same time (another return of the pulse)
    c.x += uniform(-200, 200) + (uniform(0, 49) == 0 ? 1 << 24 : 0);
    c.y += uniform(-200, 200);
    c.z += uniform(-50, 50);
    put(r, c.x);
    put(r + 4, c.y);
    put(r + 8, c.z);
    const int n = uniform(0, 15);
    const int ret = uniform(0, 3) == 0 ? uniform(0, 15) : std::min(n, uniform(1, 3));
    put(r + 12, static_cast<std::uint16_t>(
                    s.constant_attributes ? 7 : uniform(0, 65535) >> uniform(0, 12)));
    r[14] = static_cast<std::uint8_t>(ret | (n << 4));
    const int flags = s.constant_attributes ? 0 : uniform(0, 15) & uniform(0, 15);
    const int dir_edge = s.constant_attributes ? 0 : uniform(0, 3);
    r[15] = static_cast<std::uint8_t>(flags | (channel << 4) | (dir_edge << 6));
    r[16] = static_cast<std::uint8_t>(s.constant_attributes ? 2
                                      : uniform(0, 5) == 0  ? uniform(0, 255)
                                                            : 2);
    // User data: a few values mostly (adaptive models only adapt after ~130 symbols).
    const int user = uniform(0, 9) == 0 ? uniform(0, 255) : 4 * uniform(0, 3);
    r[17] = static_cast<std::uint8_t>(s.constant_attributes ? 9 : user);
    put(r + 18, static_cast<std::int16_t>(
                    s.constant_attributes ? -5 : uniform(-30000, 30000) / (1 + uniform(0, 1000))));
    put(r + 20, static_cast<std::uint16_t>(s.constant_attributes ? 17
                                           : uniform(0, 20) == 0 ? uniform(0, 65535)
                                                                 : 3));
    put(r + 22, c.gps);
}

/// The optional items after POINT14: colour (often grey, sometimes unchanged), NIR, a wave
/// packet (offsets: same, after the last packet, a difference, or far) and the extra bytes.
void fill_others(std::uint8_t* r, std::mt19937& rng, const Synthetic& s, std::size_t at) {
    auto uniform = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
    if (s.format == 7 || s.format == 8 || s.format == 10) {
        if (uniform(0, 3) != 0) {
            const int grey = uniform(0, 65535);
            for (int k = 0; k < 3; ++k) {
                put(r + at + 2 * k,
                    static_cast<std::uint16_t>(uniform(0, 2) == 0 ? uniform(0, 65535) : grey));
            }
        }
        at += 6;
        if (s.format != 7) {
            if (uniform(0, 1) == 0) {
                put(r + at, static_cast<std::uint16_t>(uniform(0, 65535)));
            }
            at += 2;
        }
    }
    if (s.format == 9 || s.format == 10) {
        r[at] = static_cast<std::uint8_t>(uniform(0, 3));
        std::uint64_t offset = 0;
        std::uint32_t size = 0;
        std::memcpy(&offset, r + at + 1, 8);
        std::memcpy(&size, r + at + 9, 4);
        const int kind = uniform(0, 3);
        offset = kind == 0   ? offset
                 : kind == 1 ? offset + size
                 : kind == 2 ? offset + static_cast<std::uint64_t>(uniform(-1000, 1000))
                             : offset + (1ULL << 40);
        put(r + at + 1, offset);
        put(r + at + 9, static_cast<std::uint32_t>(uniform(0, 3) == 0 ? uniform(0, 5000) : 256));
        put(r + at + 13, static_cast<float>(uniform(0, 100000)) * 0.5F);
        for (int k = 0; k < 3; ++k) {
            put(r + at + 17 + 4 * k, static_cast<float>(uniform(-1000, 1000)) * 1e-3F);
        }
        at += 29;
    }
    for (std::size_t k = 0; k < s.extra_bytes; ++k) {
        if (k != 1 && uniform(0, 2) == 0) {  // extra byte 1 never changes
            r[at + k] = static_cast<std::uint8_t>(uniform(0, 255));
        }
    }
}

/// The synthetic records of `s` (each starts as a copy of the previous one).
std::vector<std::uint8_t> synthetic_records(const Synthetic& s, std::size_t length) {
    std::mt19937 rng(s.seed);
    std::vector<std::uint8_t> records(s.points * length);
    std::array<SyntheticChannel, 4> channels{};
    for (std::size_t k = 0; k < 4; ++k) {
        channels[k].gps = 5e5 + 100.0 * static_cast<double>(k);
    }
    unsigned channel = 0;
    for (std::size_t p = 0; p < s.points; ++p) {
        std::uint8_t* r = records.data() + p * length;
        if (p > 0) {
            std::memcpy(r, r - length, length);
        }
        fill_point14(r, rng, channels, channel, s);
        fill_others(r, rng, s, 30);
    }
    return records;
}

/// decode(encode(records)) == records; returns the chunk's layer sizes.
std::vector<std::uint32_t> expect_round_trip(const Synthetic& s) {
    static constexpr std::size_t kCore[] = {30, 36, 38, 59, 67};
    const std::size_t length = kCore[s.format - 6] + s.extra_bytes;
    const LazVlr vlr = laz_vlr_for(s.format, length, 50000);
    const std::vector<std::uint8_t> records = synthetic_records(s, length);
    std::vector<std::uint8_t> chunk{0xAB};  // appended to, not overwritten
    encode_layered_chunk(vlr.items, records, s.points, chunk);
    EXPECT_EQ(chunk[0], 0xAB);
    const std::span<const std::uint8_t> bytes = std::span<const std::uint8_t>(chunk).subspan(1);
    std::vector<std::uint8_t> decoded(records.size());
    decode_layered_chunk(vlr.items, bytes, s.points, decoded);
    std::size_t differ = 0;
    for (std::size_t p = 0; p < s.points; ++p) {
        if (std::memcmp(decoded.data() + p * length, records.data() + p * length, length) != 0 &&
            differ++ < 3) {
            ADD_FAILURE() << "format " << s.format << " seed " << s.seed << ": record " << p
                          << " of " << s.points << " differs";
        }
    }
    EXPECT_EQ(differ, 0u);
    std::vector<std::uint32_t> sizes;
    if (s.points > 0) {
        std::size_t layers = 0;
        for (const Item& item : vlr.items) {
            layers += item.type == ItemType::point14    ? 9
                      : item.type == ItemType::rgbnir14 ? 2
                      : item.type == ItemType::byte14   ? item.size
                                                        : 1;
        }
        EXPECT_EQ(test::get<std::uint32_t>(chunk, 1 + length), s.points);
        for (std::size_t i = 0; i < layers; ++i) {
            sizes.push_back(test::get<std::uint32_t>(chunk, 1 + length + 4 + 4 * i));
        }
    }
    return sizes;
}

TEST(LazEncode, SyntheticRecordsRoundTripThroughEveryItem) {
    for (const int format : {6, 7, 8, 9, 10}) {
        for (const std::size_t extra : {std::size_t{0}, std::size_t{3}}) {
            for (std::uint32_t seed = 1; seed <= 2; ++seed) {
                SCOPED_TRACE("format " + std::to_string(format) + ", " + std::to_string(extra) +
                             " extra bytes, seed " + std::to_string(seed));
                (void)expect_round_trip({format, extra, 3000, seed, false});
            }
        }
    }
}

TEST(LazEncode, TinyChunksRoundTrip) {
    for (const std::size_t points :
         {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{3}}) {
        SCOPED_TRACE(std::to_string(points) + " points");
        (void)expect_round_trip({8, 2, points, 3, false});
    }
    std::vector<std::uint8_t> out;
    encode_layered_chunk(laz_vlr_for(6, 30, 50000).items, {}, 0, out);
    EXPECT_TRUE(out.empty());
}

TEST(LazEncode, UnchangedLayersAreEmpty) {
    // Format 6 + 2 extra bytes: XY, Z, classification, flags, intensity, scan angle, user data,
    // point source, GPS time, then the two bytes (the second never changes).
    const std::vector<std::uint32_t> constant = expect_round_trip({6, 2, 500, 5, true});
    ASSERT_EQ(constant.size(), 11u);
    EXPECT_GT(constant[0], 0u);  // XY
    EXPECT_GT(constant[1], 0u);  // Z: LASzip always writes it
    for (const std::size_t i : {2, 3, 4, 5, 6, 7}) {
        EXPECT_EQ(constant[i], 0u) << "layer " << i;
    }
    EXPECT_GT(constant[8], 0u);   // GPS time
    EXPECT_GT(constant[9], 0u);   // extra byte 0
    EXPECT_EQ(constant[10], 0u);  // extra byte 1
    const std::vector<std::uint32_t> varied = expect_round_trip({6, 2, 500, 5, false});
    ASSERT_EQ(varied.size(), 11u);
    for (std::size_t i = 0; i < 10; ++i) {
        EXPECT_GT(varied[i], 0u) << "layer " << i;
    }
}

TEST(LazEncode, RefusesItemsItCannotEncode) {
    std::vector<std::uint8_t> out;
    const std::vector<std::uint8_t> record(28);
    EXPECT_THROW(encode_layered_chunk(laz_vlr_for(1, 28, 50000).items, record, 1, out),
                 std::invalid_argument);
    std::vector<Item> items = laz_vlr_for(6, 30, 50000).items;
    EXPECT_THROW(encode_layered_chunk(items, record, 1, out), std::invalid_argument);  // 28 bytes
    items[0].version = 4;
    EXPECT_THROW(encode_layered_chunk(items, std::vector<std::uint8_t>(30), 1, out),
                 std::invalid_argument);
    EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace beamtrace::laz
