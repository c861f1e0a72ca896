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

}  // namespace
}  // namespace beamtrace::laz
