// The LAZ writer's codec (laz/laz_encode.hpp) against LASzip's own bytes: the layered chunks of
// real LAZ files re-encoded from their decoded records, the LASzip VLR for their point format and
// their chunk tables; then round trips of synthetic records through every layered item.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
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
    // Format 6 (LAStools 3.4r3; LASzip 2.2 with an EVLR), 8 with BYTE14 (LASzip 2.2; 3.4r3),
    // COPC (variable chunks: format 6, and 7 with RGB14), 10 with WAVEPACKET14 (3.4r4).
    EXPECT_EQ(reencode_chunks("las/laz/las14_prf6.laz", 10), 1u);
    EXPECT_EQ(reencode_chunks("las/laz/1_4_w_evlr.laz", 10), 1u);
    EXPECT_EQ(reencode_chunks("las/laz/append-bug.laz", 10), 1u);
    EXPECT_EQ(reencode_chunks("las/laz/las_with_several_extra_byte_bloc.laz", 2), 2u);
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

}  // namespace
}  // namespace beamtrace::laz
