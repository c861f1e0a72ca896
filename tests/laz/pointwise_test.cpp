// Point-wise chunks (compressor 1 and 2, items of version 1 and 2) against real LAZ files and
// their LAS twins, and the version-2 encoders by round trip and against LASzip's own bytes.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <random>
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

/// The bounds of the decoded x, y, z equal the header's minimum and maximum.
void expect_header_bounds(const test::LasTestFile& f, const std::vector<std::uint8_t>& out) {
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
        EXPECT_NEAR(lo, min, 0.5 * scale) << "axis " << axis;
        EXPECT_NEAR(hi, max, 0.5 * scale) << "axis " << axis;
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

}  // namespace
}  // namespace beamtrace::laz
