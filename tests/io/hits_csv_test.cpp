#include "beamtrace/io/hits_csv.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>

#include "beamtrace/core/error.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

HitBatch small_batch() {
    HitBatch hits;
    hits.resize(4);
    hits.t[0] = 12.5f;
    hits.face[0] = 7;
    hits.t[2] = 0.1f;
    hits.face[2] = 4'000'000'000u;
    hits.t[3] = 1e-3f;
    hits.face[3] = 0;
    return hits;  // ray 1 is a miss
}

TEST(HitsCsv, WritesHeaderRowsAndMissesExactly) {
    test::TempDir dir;
    const fs::path path = dir.path() / "hits.csv";
    write_hits_csv(path, small_batch());
    EXPECT_EQ(test::read_file(path),
              "ray,range_m,face_id\n"
              "0,12.5,7\n"
              "1,inf,-1\n"
              "2,0.1,4000000000\n"
              "3,0.001,0\n");
}

TEST(HitsCsv, RoundTripReproducesEveryFloat) {
    test::TempDir dir;
    const fs::path path = dir.path() / "hits.csv";
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> range(0.0f, 2000.0f);
    HitBatch hits;
    hits.resize(20'000);
    for (std::size_t i = 0; i < hits.size(); ++i) {
        if (i % 7 != 3) {
            hits.t[i] = range(rng);
            hits.face[i] = static_cast<std::uint32_t>(rng() % 1'000'000);
        }
    }
    hits.t[1] = std::numeric_limits<float>::denorm_min();
    hits.t[2] = std::numeric_limits<float>::max();
    write_hits_csv(path, hits);

    const HitsCsv table = read_hits_csv(path);
    ASSERT_EQ(table.size(), hits.size());
    for (std::size_t i = 0; i < hits.size(); ++i) {
        ASSERT_EQ(table.ray[i], i);
        if (hits.hit(i)) {
            ASSERT_EQ(std::bit_cast<std::uint32_t>(static_cast<float>(table.range_m[i])),
                      std::bit_cast<std::uint32_t>(hits.t[i]))
                << "row " << i;
            ASSERT_EQ(table.face_id[i], std::int64_t{hits.face[i]});
        } else {
            ASSERT_EQ(table.range_m[i], std::numeric_limits<double>::infinity());
            ASSERT_EQ(table.face_id[i], -1);
        }
    }
}

TEST(HitsCsv, EmptyBatchIsJustTheHeader) {
    test::TempDir dir;
    const fs::path path = dir.path() / "empty.csv";
    write_hits_csv(path, HitBatch{});
    EXPECT_EQ(test::read_file(path), "ray,range_m,face_id\n");
    EXPECT_EQ(read_hits_csv(path).size(), 0u);
}

TEST(HitsCsv, MismatchedBatchIsAnOutputError) {
    test::TempDir dir;
    HitBatch hits = small_batch();
    hits.face.pop_back();
    EXPECT_THROW(write_hits_csv(dir.path() / "x.csv", hits), OutputError);
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(HitsCsv, ReaderReportsFileAndLine) {
    test::TempDir dir;
    const fs::path path = dir.path() / "broken.csv";
    const auto expect_error_at = [&](const std::string& text, const std::string& location) {
        test::expect_input_error(read_hits_csv, test::write_file(path, text),
                                 path.string() + location);
    };
    expect_error_at("", ":");
    expect_error_at("x,y,z\n0,1,2\n", ":1:");
    expect_error_at("ray,range_m,face_id\n0,1.5,2\n1,2.5\n", ":3:");
    expect_error_at("ray,range_m,face_id\n0,abc,2\n", ":2:");
    expect_error_at("ray,range_m,face_id\n0,1,2,3\n", ":2:");
    expect_error_at("ray,range_m,face_id\n0,1,2x\n", ":2:");
}

TEST(HitsCsv, ReaderAcceptsCrlf) {
    test::TempDir dir;
    const fs::path path = dir.path() / "crlf.csv";
    test::write_file(path, "ray,range_m,face_id\r\n0,1.5,2\r\n1,inf,-1\r\n");
    const HitsCsv table = read_hits_csv(path);
    ASSERT_EQ(table.size(), 2u);
    EXPECT_EQ(table.range_m[0], 1.5);
    EXPECT_EQ(table.face_id[1], -1);
}

}  // namespace
}  // namespace beamtrace
