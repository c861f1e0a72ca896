// Broken LAZ files: damaged chunk tables (missing, hostile counts, offset at the end), truncated
// and corrupted chunks. Every one reads correctly or gives an InputError naming the file, never a
// crash or a huge allocation.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "../test_support.hpp"
#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "laz/laz_items.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

template <typename T>
T get(const std::string& b, std::size_t at) {
    T v;
    std::memcpy(&v, b.data() + at, sizeof v);
    return v;
}

template <typename T>
void put(std::string& b, std::size_t at, T v) {
    std::memcpy(b.data() + at, &v, sizeof v);
}

std::vector<LasPoint> read_points(const fs::path& path) {
    return read_las_points(path);
}

class LazCorruption : public test::TempDirTest {
  protected:
    [[nodiscard]] fs::path write_laz(const std::string& bytes) const {
        return write("f.laz", bytes);
    }
};

TEST_F(LazCorruption, ChunkTableOffsetAtTheEndOfTheFileIsFollowed) {
    const fs::path original = test::shared_data("las/laz/lone-star.copc.laz");
    BEAMTRACE_REQUIRE_FILE(original);
    std::string b = test::read_file(original);
    const auto start = get<std::uint32_t>(b, 96);
    const auto table = get<std::int64_t>(b, start);
    put<std::int64_t>(b, start, -1);
    b.append(reinterpret_cast<const char*>(&table), 8);
    EXPECT_EQ(read_points(write_laz(b)), read_points(original));
}

TEST_F(LazCorruption, PointwiseFileOfManyChunksWithoutAUsableTableIsAClearError) {
    const fs::path original = test::shared_data("las/laz/autzen_trim.laz");
    BEAMTRACE_REQUIRE_FILE(original);
    const std::string good = test::read_file(original);
    const auto start = get<std::uint32_t>(good, 96);
    const auto table = static_cast<std::size_t>(get<std::int64_t>(good, start));
    std::string b = good;
    put<std::uint32_t>(b, table + 4, 0xFFFFFFFFU);  // 2^32 - 1 chunks in a 600 kB file
    test::expect_input_error(read_points, write_laz(b), "chunk table: 4294967295 chunks");
    b = good;
    put<std::int64_t>(b, start, static_cast<std::int64_t>(start));  // interrupted writer
    test::expect_input_error(read_points, write_laz(b), "span more than one chunk");
    b = good;
    put<std::int64_t>(b, start, std::int64_t{1} << 40);
    test::expect_input_error(read_points, write_laz(b), "table offset is missing");
    b = good;
    put<std::uint32_t>(b, table, 7);
    test::expect_input_error(read_points, write_laz(b), "unknown table version 7");
}

TEST_F(LazCorruption, LayeredChunksAreFoundByAScanWithoutATable) {
    for (const char* name : {"las/laz/lone-star.copc.laz", "las/laz/append-bug.laz"}) {
        SCOPED_TRACE(name);
        const fs::path original = test::shared_data(name);
        BEAMTRACE_REQUIRE_FILE(original);
        const std::vector<LasPoint> expected = read_points(original);
        const std::string good = test::read_file(original);
        const auto start = get<std::uint32_t>(good, 96);
        const auto table = static_cast<std::size_t>(get<std::int64_t>(good, start));
        std::string b = good;
        put<std::uint32_t>(b, table + 4, 0xFFFFFFFFU);
        EXPECT_EQ(read_points(write_laz(b)), expected);
        b = good;
        put<std::int64_t>(b, start, static_cast<std::int64_t>(start));
        EXPECT_EQ(read_points(write_laz(b)), expected);
    }
    // A chunk cut short: the scan names it (append-bug.laz has no EVLR to miss first).
    std::string b = test::read_file(test::shared_data("las/laz/append-bug.laz"));
    const auto start = get<std::uint32_t>(b, 96);
    b.resize(start + 8 + 40000);
    put<std::int64_t>(b, start, -1);
    test::expect_input_error(read_points, write_laz(b), "scanning the chunks, chunk 1 at byte");
}

TEST_F(LazCorruption, AOneChunkFileReadsWithoutItsTable) {
    const fs::path original = test::shared_data("las/laz/simple.laz");
    BEAMTRACE_REQUIRE_FILE(original);
    std::string b = test::read_file(original);
    const auto start = get<std::uint32_t>(b, 96);
    const auto table = static_cast<std::size_t>(get<std::int64_t>(b, start));
    put<std::int64_t>(b, start, -1);
    b.resize(table);  // the table is gone, and the last 8 bytes are chunk data
    const std::vector<LasPoint> points = read_points(write_laz(b));
    EXPECT_EQ(points, read_points(original));
}

TEST_F(LazCorruption, TruncatedLayeredFilesAreRefusedWithTheirChunk) {
    const fs::path original = test::shared_data("las/laz/append-bug.laz");
    BEAMTRACE_REQUIRE_FILE(original);
    const std::string good = test::read_file(original);
    const auto start = get<std::uint32_t>(good, 96);
    const auto table = static_cast<std::size_t>(get<std::int64_t>(good, start));
    std::string b = good;
    // Cut the middle out of the chunk data but keep the table: chunks now run past the table.
    b.erase(start + 5000, 20000);
    put<std::int64_t>(b, start, static_cast<std::int64_t>(table - 20000));
    const std::string message = test::expect_input_error(read_points, write_laz(b), "chunk");
    EXPECT_NE(message.find("LAZ"), std::string::npos) << message;
}

TEST_F(LazCorruption, RandomByteFlipsInTheChunksNeverCrash) {
    const fs::path original = test::shared_data("las/laz/1_4_w_evlr.laz");
    BEAMTRACE_REQUIRE_FILE(original);
    const std::string good = test::read_file(original);
    const auto start = get<std::uint32_t>(good, 96);
    const std::vector<LasPoint> expected = read_points(original);
    std::mt19937 rng(7);
    int refused = 0, changed = 0;
    for (int i = 0; i < 200; ++i) {
        std::string b = good;
        const std::size_t at = start + 8 + rng() % (good.size() - start - 8);
        b[at] = static_cast<char>(b[at] ^ (1 + rng() % 255));
        try {
            changed += read_points(write_laz(b)) != expected ? 1 : 0;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("f.laz"), std::string::npos);
            ++refused;
        }
    }
    EXPECT_GT(refused + changed, 100);  // most flips are noticed one way or the other
}

TEST(LayeredChunk, ShortOrInconsistentChunksThrowCorruptData) {
    const std::vector<laz::Item> items = {{laz::ItemType::point14, 30, 3}};
    std::vector<std::uint8_t> out(2 * 30);
    std::vector<std::uint8_t> bytes(30 + 4 + 36, 0);
    EXPECT_THROW(laz::decode_layered_chunk(items, std::span(bytes).first(20), 2, out),
                 laz::CorruptData);
    // The chunk says 3 points, the table 2.
    bytes[30] = 3;
    EXPECT_THROW(laz::decode_layered_chunk(items, bytes, 2, out), laz::CorruptData);
    // A layer claiming more bytes than the chunk holds.
    bytes[30] = 2;
    bytes[34] = 200;
    EXPECT_THROW(laz::decode_layered_chunk(items, bytes, 2, out), laz::CorruptData);
    // Output of the wrong size.
    bytes[34] = 0;
    std::vector<std::uint8_t> small(30);
    EXPECT_THROW(laz::decode_layered_chunk(items, bytes, 2, small), laz::CorruptData);
    // A wave packet item: refused, not misread.
    const std::vector<laz::Item> waves = {{laz::ItemType::point14, 30, 3},
                                          {laz::ItemType::wavepacket14, 29, 3}};
    std::vector<std::uint8_t> out2(2 * 59);
    EXPECT_THROW(laz::decode_layered_chunk(waves, bytes, 2, out2), laz::CorruptData);
}

TEST(LayeredChunk, OnePointChunkIsItsRawRecord) {
    const std::vector<laz::Item> items = {{laz::ItemType::point14, 30, 3},
                                          {laz::ItemType::byte14, 2, 3}};
    std::vector<std::uint8_t> bytes(32 + 4 + 4 * 11, 0);
    for (std::size_t i = 0; i < 32; ++i) {
        bytes[i] = static_cast<std::uint8_t>(i * 7 + 1);
    }
    bytes[32] = 1;
    std::vector<std::uint8_t> out(32);
    laz::decode_layered_chunk(items, bytes, 1, out);
    EXPECT_TRUE(std::equal(out.begin(), out.end(), bytes.begin()));
}

}  // namespace
}  // namespace beamtrace
