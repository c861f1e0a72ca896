#include "beamtrace/io/hits_csv.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

class TempDir {
  public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() / ("beamtrace-" + std::string(info->test_suite_name()) +
                                             "-" + info->name() + "-" + std::to_string(::getpid()));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    [[nodiscard]] const fs::path& path() const { return path_; }

  private:
    fs::path path_;
};

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

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
    TempDir dir;
    const fs::path path = dir.path() / "hits.csv";
    write_hits_csv(path, small_batch());
    EXPECT_EQ(slurp(path),
              "ray,range_m,face_id\n"
              "0,12.5,7\n"
              "1,inf,-1\n"
              "2,0.1,4000000000\n"
              "3,0.001,0\n");
}

TEST(HitsCsv, RoundTripReproducesEveryFloat) {
    TempDir dir;
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
    TempDir dir;
    const fs::path path = dir.path() / "empty.csv";
    write_hits_csv(path, HitBatch{});
    EXPECT_EQ(slurp(path), "ray,range_m,face_id\n");
    EXPECT_EQ(read_hits_csv(path).size(), 0u);
}

TEST(HitsCsv, MismatchedBatchIsAnOutputError) {
    TempDir dir;
    HitBatch hits = small_batch();
    hits.face.pop_back();
    EXPECT_THROW(write_hits_csv(dir.path() / "x.csv", hits), OutputError);
    EXPECT_TRUE(fs::is_empty(dir.path()));
}

TEST(HitsCsv, ReaderReportsFileAndLine) {
    TempDir dir;
    const fs::path path = dir.path() / "broken.csv";
    const auto expect_error_at = [&](const std::string& text, const std::string& location) {
        spit(path, text);
        try {
            static_cast<void>(read_hits_csv(path));
            ADD_FAILURE() << "expected InputError for:\n" << text;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(path.string() + location), std::string::npos)
                << e.what();
        }
    };
    expect_error_at("", ":");
    expect_error_at("x,y,z\n0,1,2\n", ":1:");
    expect_error_at("ray,range_m,face_id\n0,1.5,2\n1,2.5\n", ":3:");
    expect_error_at("ray,range_m,face_id\n0,abc,2\n", ":2:");
    expect_error_at("ray,range_m,face_id\n0,1,2,3\n", ":2:");
    expect_error_at("ray,range_m,face_id\n0,1,2x\n", ":2:");
}

TEST(HitsCsv, ReaderAcceptsCrlf) {
    TempDir dir;
    const fs::path path = dir.path() / "crlf.csv";
    spit(path, "ray,range_m,face_id\r\n0,1.5,2\r\n1,inf,-1\r\n");
    const HitsCsv table = read_hits_csv(path);
    ASSERT_EQ(table.size(), 2u);
    EXPECT_EQ(table.range_m[0], 1.5);
    EXPECT_EQ(table.face_id[1], -1);
}

}  // namespace
}  // namespace beamtrace
