// compute_las_stats and las_info_json against independent computations: hand-made points whose
// statistics the test computes by brute force (long double), and a real file whose records the
// test decodes from the raw bytes itself.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <map>
#include <vector>

#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/io/las_stats.hpp"
#include "beamtrace/io/las_writer.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

/// Brute-force statistics of one field.
struct Brute {
    long double sum = 0;
    double min = 1e300, max = -1e300;
    void add(double v) {
        sum += v;
        min = std::min(min, v);
        max = std::max(max, v);
    }
};

void expect_field(const LasFieldStats& f, const Brute& b, std::size_t n, double tol,
                  const char* name) {
    EXPECT_EQ(f.min, b.min) << name;
    EXPECT_EQ(f.max, b.max) << name;
    EXPECT_NEAR(f.mean, static_cast<double>(b.sum / static_cast<long double>(n)), tol) << name;
}

/// 150 000 points (more than two reader chunks) with every counted field varying.
std::vector<LasPoint> made_points() {
    std::vector<LasPoint> points(150000);
    for (std::size_t i = 0; i < points.size(); ++i) {
        LasPoint& p = points[i];
        p.x = 500000.0 + static_cast<double>(i % 1000) * 0.25;  // 0 .. 249.75
        p.y = 5400000.0 + static_cast<double>(i / 1000) * 0.5;  // 0 .. 74.5
        p.z = 100.0 + static_cast<double>(i % 97) * 0.013;
        p.intensity = static_cast<std::uint16_t>((i * 37) % 65536);
        p.number_of_returns = static_cast<std::uint8_t>(1 + i % 7);
        p.return_number = static_cast<std::uint8_t>(1 + i % p.number_of_returns);
        p.classification = static_cast<std::uint8_t>(i % 3 == 0 ? 2 : (i % 11 == 0 ? 200 : 5));
        p.gps_time = 1e9 + static_cast<double>(i) * 1e-5;
    }
    return points;
}

TEST(LasStats, MatchesBruteForceOverKnownPoints) {
    const std::vector<LasPoint> points = made_points();
    test::TempDir dir;
    LasWriterConfig config = las_config_for_extent({500000, 5400000, 0}, {501000, 5401000, 200});
    LasWriter writer(dir / "made.las", config);
    writer.write(points);
    writer.close();
    Brute x, y, z, intensity, gps;
    std::map<int, std::uint64_t> cls, ret, nret;
    for (const LasPoint& p : points) {
        // Expected values are the quantized coordinates (1 mm steps): round here, not by reader.
        x.add(std::round((p.x - config.offset.x) / config.scale.x) * config.scale.x +
              config.offset.x);
        y.add(std::round((p.y - config.offset.y) / config.scale.y) * config.scale.y +
              config.offset.y);
        z.add(std::round((p.z - config.offset.z) / config.scale.z) * config.scale.z +
              config.offset.z);
        intensity.add(p.intensity);
        gps.add(p.gps_time);
        ++cls[p.classification];
        ++ret[p.return_number];
        ++nret[p.number_of_returns];
    }
    LasReader reader(dir / "made.las");
    std::vector<std::size_t> calls;
    const LasStats s = compute_las_stats(reader, [&](std::size_t done, std::size_t total) {
        EXPECT_EQ(total, points.size());
        calls.push_back(done);
    });
    EXPECT_EQ(calls, (std::vector<std::size_t>{65536, 131072, 150000}));
    const std::size_t n = points.size();
    ASSERT_EQ(s.points, n);
    expect_field(s.x, x, n, 1e-6, "x");
    expect_field(s.y, y, n, 1e-6, "y");
    expect_field(s.z, z, n, 1e-9, "z");
    expect_field(s.intensity, intensity, n, 1e-9, "intensity");
    ASSERT_TRUE(s.gps_time);
    expect_field(*s.gps_time, gps, n, 1e-6, "gps time");
    for (int v = 0; v < 256; ++v) {
        EXPECT_EQ(s.by_classification[static_cast<std::size_t>(v)], cls[v]) << v;
    }
    for (int v = 0; v < 16; ++v) {
        EXPECT_EQ(s.by_return_number[static_cast<std::size_t>(v)], ret[v]) << v;
        EXPECT_EQ(s.by_number_of_returns[static_cast<std::size_t>(v)], nret[v]) << v;
    }
    EXPECT_NEAR(s.footprint_area, 249.75 * 74.5, 1e-6);
    ASSERT_TRUE(s.density_per_area);
    EXPECT_NEAR(*s.density_per_area, 150000.0 / (249.75 * 74.5), 1e-9);

    const auto json = nlohmann::json::parse(
        las_info_json(dir / "made.las", reader.header(), reader.vlrs(), s.crs, &s));
    EXPECT_EQ(json.at("stats").at("points"), n);
    EXPECT_EQ(json.at("stats").at("by_classification").at("200"), cls[200]);
    EXPECT_FALSE(json.at("stats").at("by_classification").contains("0"));
    EXPECT_EQ(json.at("stats").at("x").at("min").get<double>(), x.min);
    EXPECT_EQ(json.at("stats").at("gps_time").at("max").get<double>(), gps.max);
    EXPECT_EQ(json.at("crs").at("source"), "none");
    EXPECT_EQ(json.at("point_count"), n);
}

std::uint16_t u16(const std::string& b, std::size_t at) {
    std::uint16_t v = 0;
    std::memcpy(&v, b.data() + at, 2);
    return v;
}
std::int32_t i32(const std::string& b, std::size_t at) {
    std::int32_t v = 0;
    std::memcpy(&v, b.data() + at, 4);
    return v;
}
double f64(const std::string& b, std::size_t at) {
    double v = 0;
    std::memcpy(&v, b.data() + at, 8);
    return v;
}

TEST(LasStats, MatchesARawDecodeOfARealFile) {
    const fs::path path = test::shared_data("las/las/simple.las");  // LAS 1.2, format 3
    BEAMTRACE_REQUIRE_FILE(path);
    const std::string b = test::read_file(path);
    ASSERT_EQ(b[104], 3);
    const std::size_t first = static_cast<std::size_t>(i32(b, 96));
    const std::size_t length = u16(b, 105);
    const std::size_t n = static_cast<std::size_t>(i32(b, 107));
    Brute x, y, z, intensity, gps;
    std::map<int, std::uint64_t> cls, ret;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t r = first + i * length;
        x.add(i32(b, r) * f64(b, 131) + f64(b, 155));
        y.add(i32(b, r + 4) * f64(b, 139) + f64(b, 163));
        z.add(i32(b, r + 8) * f64(b, 147) + f64(b, 171));
        intensity.add(u16(b, r + 12));
        ++ret[static_cast<unsigned char>(b[r + 14]) & 7];
        ++cls[static_cast<unsigned char>(b[r + 15]) & 31];
        gps.add(f64(b, r + 20));
    }
    LasReader reader(path);
    const LasStats s = compute_las_stats(reader);
    ASSERT_EQ(s.points, n);
    expect_field(s.x, x, n, 1e-6, "x");
    expect_field(s.y, y, n, 1e-6, "y");
    expect_field(s.z, z, n, 1e-6, "z");
    expect_field(s.intensity, intensity, n, 1e-9, "intensity");
    ASSERT_TRUE(s.gps_time);
    expect_field(*s.gps_time, gps, n, 1e-6, "gps time");
    for (const auto& [v, count] : cls) {
        EXPECT_EQ(s.by_classification[static_cast<std::size_t>(v)], count) << v;
    }
    for (const auto& [v, count] : ret) {
        EXPECT_EQ(s.by_return_number[static_cast<std::size_t>(v)], count) << v;
    }
}

TEST(LasStats, EmptyFileHasNoFieldsAndNoDensity) {
    const fs::path path = test::shared_data("las/edge/no-points.las");
    BEAMTRACE_REQUIRE_FILE(path);
    LasReader reader(path);
    const LasStats s = compute_las_stats(reader);
    EXPECT_EQ(s.points, 0u);
    EXPECT_FALSE(s.density_per_area);
    const auto json =
        nlohmann::json::parse(las_info_json(path, reader.header(), reader.vlrs(), s.crs, &s));
    EXPECT_TRUE(json.at("stats").at("x").is_null());
    EXPECT_TRUE(json.at("stats").at("density_per_area").is_null());
}

}  // namespace
}  // namespace beamtrace
