// The point sinks of the registry: the streamed PLY writes exactly write_points_ply's bytes
// whatever the blocks; every sink, aborted or destroyed before commit(), leaves no file, and a
// commit leaves exactly the files it names (no temporary files).
#include "beamtrace/io/point_sink.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/point_cloud_ply.hpp"
#include "beamtrace/io/point_sink_registry.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

std::set<std::string> files_in(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) {
        names.insert(e.path().filename().string());
    }
    return names;
}

std::vector<BlockPoint> random_points(std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1e4, 1e4);
    std::vector<BlockPoint> points(n);
    for (std::size_t i = 0; i < n; ++i) {
        BlockPoint& p = points[i];
        p.x = u(rng);
        p.y = u(rng);
        p.z = u(rng);
        p.gps_time = 1e-3 * static_cast<double>(i);
        p.range_m = static_cast<float>(std::abs(u(rng)));
        p.face = i % 7 == 3 ? 0xFFFFFFFFu : static_cast<std::uint32_t>(rng() % 100000);
        p.intensity = static_cast<std::uint16_t>(rng());
        p.classification = static_cast<std::uint8_t>(1 + rng() % 30);
        p.point_source_id = static_cast<std::uint16_t>(rng());
        p.channel = static_cast<std::uint16_t>(rng() % 64);
        p.pulse = i / 2;  // two returns per pulse
        p.return_number = static_cast<std::uint8_t>(1 + i % 2);
        p.number_of_returns = 2;
    }
    return points;
}

/// Feeds `points` to `sink` in blocks of the given sizes (cycled), encoding each on its own.
void feed(PointSink& sink, const std::vector<BlockPoint>& points,
          const std::vector<std::size_t>& sizes) {
    PointBlock block;
    const auto buffer = sink.make_buffer();
    std::size_t next = 0;
    for (std::size_t k = 0; next < points.size(); ++k) {
        const std::size_t n = std::min(sizes[k % sizes.size()], points.size() - next);
        block.clear();
        block.points.assign(points.begin() + static_cast<std::ptrdiff_t>(next),
                            points.begin() + static_cast<std::ptrdiff_t>(next + n));
        buffer->clear();
        sink.encode(block, *buffer);
        sink.write(*buffer);
        next += n;
    }
}

SinkFacts all_facts(const fs::path& dir) {
    SinkFacts f;
    f.output_dir = dir;
    f.physics = true;
    f.lo_m = {-1e4, -1e4, -1e4};
    f.hi_m = {1e4, 1e4, 1e4};
    f.provenance = "test";
    f.comment = "sink test\nsecond line";
    f.image = ImageGrid{100, 50};
    f.waveform = WaveformFacts{};
    f.trajectory = SampledTrajectory({{0.0, {0, 0, 0}, {}}, {1.0, {1, 0, 0}, {}}});
    f.trajectory_rate_hz = 2.0;
    return f;
}

TEST(PointSinks, StreamedPlyIsByteIdenticalToTheInMemoryWriter) {
    for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{5000}}) {
        test::TempDir dir;
        const std::vector<BlockPoint> points = random_points(n, 7);
        std::vector<PointRecord> records;
        for (const BlockPoint& p : points) {
            records.push_back(
                {p.x, p.y, p.z, p.range_m, p.face, static_cast<std::uint32_t>(p.pulse)});
        }
        fs::create_directories(dir / "memory");
        write_points_ply(dir / "memory" / "points.ply", records, "sink test\nsecond line");
        const auto sink = point_sink("ply").make(all_facts(dir.path()));
        feed(*sink, points, {1, 1000, 0, 37, 4096});
        EXPECT_EQ(files_in(dir.path()).size(), 2u) << "the body's temporary file";
        EXPECT_EQ(sink->commit(), std::vector<fs::path>{dir / "points.ply"});
        EXPECT_EQ(files_in(dir.path()), (std::set<std::string>{"memory", "points.ply"}));
        EXPECT_EQ(test::read_file(dir / "points.ply"),
                  test::read_file(dir / "memory" / "points.ply"))
            << n << " points";
        EXPECT_EQ(read_points_ply(dir / "points.ply").size(), n);
    }
}

TEST(PointSinks, AbortedOrUncommittedSinksLeaveNoFileAndCommittedOnesOnlyTheirs) {
    const std::vector<BlockPoint> points = random_points(3000, 3);
    for (const SinkEntry& entry : point_sinks()) {
        SCOPED_TRACE(std::string(entry.name));
        test::TempDir dir;
        const SinkFacts facts = all_facts(dir.path());
        ASSERT_TRUE(entry.applies(facts));
        {
            const auto sink = entry.make(facts);
            feed(*sink, points, {1024});
            sink->abort();
            EXPECT_TRUE(files_in(dir.path()).empty()) << "after abort()";
        }
        {
            const auto sink = entry.make(facts);
            feed(*sink, points, {1024});
        }
        EXPECT_TRUE(files_in(dir.path()).empty()) << "destroyed without commit()";
        std::set<std::string> listed;
        {
            const auto sink = entry.make(facts);
            feed(*sink, points, {1024});
            for (const fs::path& f : sink->commit()) {
                EXPECT_EQ(f.parent_path(), dir.path());
                EXPECT_GT(fs::file_size(f), 0u) << f;
                listed.insert(f.filename().string());
            }
        }
        EXPECT_FALSE(listed.empty());
        EXPECT_EQ(files_in(dir.path()), listed) << "no temporary file is left";
    }
}

TEST(PointSinks, RegistryNamesEachSinkOnceAndRefusesUnknownNames) {
    std::set<std::string_view> names, keys;
    for (const SinkEntry& e : point_sinks()) {
        EXPECT_TRUE(names.insert(e.name).second) << e.name;
        EXPECT_TRUE(e.key.empty() || keys.insert(e.key).second) << e.key;
        EXPECT_NE(e.make, nullptr);
        EXPECT_NE(e.applies, nullptr);
        EXPECT_EQ(&point_sink(e.name), &e);
    }
    for (const char* n : {"las", "laz", "csv", "ply", "pcd", "images", "waveforms", "trajectory"}) {
        EXPECT_EQ(names.count(n), 1u) << n;
    }
    try {
        (void)point_sink("e57");
        FAIL() << "no exception";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown output 'e57' (known: las, laz,"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace beamtrace
