// The PCD sink (the door's demonstration: one file and one registry line): `output: {pcd: true}`
// writes points.pcd, read back here from the PCD v0.7 specification alone and compared with
// the LAS points, point for point.
#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "beamtrace/pipeline/survey.hpp"
#include "pipeline/survey_outputs_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

struct PcdPoint {
    double x = 0, y = 0, z = 0, gps_time = 0;
    float range = 0;
    std::uint16_t intensity = 0, ring = 0;
    std::uint8_t return_number = 0, number_of_returns = 0, classification = 0;
};

/// The header lines up to DATA (as "KEY rest" pairs) and the binary records after it.
std::vector<PcdPoint> parse_pcd(const std::string& bytes,
                                std::vector<std::pair<std::string, std::string>>& header) {
    std::size_t at = 0;
    for (;;) {
        const std::size_t eol = bytes.find('\n', at);
        EXPECT_NE(eol, std::string::npos) << "unterminated header";
        if (eol == std::string::npos) {
            return {};
        }
        const std::string line = bytes.substr(at, eol - at);
        at = eol + 1;
        if (line.starts_with("#")) {
            continue;
        }
        const std::size_t space = line.find(' ');
        header.emplace_back(line.substr(0, space), line.substr(space + 1));
        if (header.back().first == "DATA") {
            break;
        }
    }
    std::vector<PcdPoint> points;
    constexpr std::size_t kRecord = 43;  // 8 8 8 2 1 1 1 8 4 2 bytes
    EXPECT_EQ((bytes.size() - at) % kRecord, 0u);
    for (; at + kRecord <= bytes.size(); at += kRecord) {
        PcdPoint p;
        const char* r = bytes.data() + at;
        std::memcpy(&p.x, r, 8);
        std::memcpy(&p.y, r + 8, 8);
        std::memcpy(&p.z, r + 16, 8);
        std::memcpy(&p.intensity, r + 24, 2);
        p.return_number = static_cast<std::uint8_t>(r[26]);
        p.number_of_returns = static_cast<std::uint8_t>(r[27]);
        p.classification = static_cast<std::uint8_t>(r[28]);
        std::memcpy(&p.gps_time, r + 29, 8);
        std::memcpy(&p.range, r + 37, 4);
        std::memcpy(&p.ring, r + 41, 2);
        points.push_back(p);
    }
    return points;
}

TEST(SurveyPcd, PcdOutputHoldsTheLasPointsWithTheirAttributes) {
    test::TempDir dir;
    const test::RawLas las = test::run_survey_raw(R"(scene: demo
scanner: {type: line, pulse_rate_hz: 20000, scan_rate_hz: 20, scan_angle_max_deg: 25,
          waveform: triangle, duration_s: 0.1}
platform: {type: legs, speed_mps: 50, waypoints_m: [[-30, 0, 150], [30, 0, 150]]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 2, rings: 1}
  returns: {mode: all, max: 5}
output: {pcd: true, csv: true, trajectory_rate_hz: 0}
)",
                                                  dir);
    ASSERT_GT(las.points.size(), 1000u);
    std::vector<std::pair<std::string, std::string>> header;
    const std::vector<PcdPoint> pcd =
        parse_pcd(test::read_file(dir / "out" / "points.pcd"), header);
    const std::string n = std::to_string(las.points.size());
    const std::vector<std::pair<std::string, std::string>> expected = {
        {"VERSION", "0.7"},
        {"FIELDS",
         "x y z intensity return_number number_of_returns classification gps_time "
         "range ring"},
        {"SIZE", "8 8 8 2 1 1 1 8 4 2"},
        {"TYPE", "F F F U U U U F F U"},
        {"COUNT", "1 1 1 1 1 1 1 1 1 1"},
        {"WIDTH", n},
        {"HEIGHT", "1"},
        {"VIEWPOINT", "0 0 0 1 0 0 0"},
        {"POINTS", n},
        {"DATA", "binary"}};
    EXPECT_EQ(header, expected);
    ASSERT_EQ(pcd.size(), las.points.size());
    const auto csv = test::read_file(dir / "out" / "points.csv");
    std::istringstream rows(csv);
    std::string row;
    std::getline(rows, row);  // the CSV's header
    bool multiple = false;
    for (std::size_t i = 0; i < pcd.size(); ++i) {
        const PcdPoint& p = pcd[i];
        const test::RawLasPoint& q = las.points[i];
        // LAS quantises to 1 mm; the PCD keeps the doubles.
        ASSERT_NEAR(p.x, q.x, 0.0005 + 1e-9) << i;
        ASSERT_NEAR(p.y, q.y, 0.0005 + 1e-9) << i;
        ASSERT_NEAR(p.z, q.z, 0.0005 + 1e-9) << i;
        ASSERT_EQ(p.gps_time, q.gps_time) << i;
        ASSERT_EQ(p.intensity, q.intensity) << i;
        ASSERT_EQ(p.return_number, q.return_number) << i;
        ASSERT_EQ(p.number_of_returns, q.number_of_returns) << i;
        ASSERT_EQ(p.classification, q.classification) << i;
        ASSERT_EQ(p.ring & 0xFF, q.user_data) << i;
        multiple = multiple || p.number_of_returns > 1;
        // The range as the CSV prints it (column 5).
        ASSERT_TRUE(std::getline(rows, row));
        std::istringstream fields(row);
        std::string field;
        for (int c = 0; c < 5; ++c) {
            std::getline(fields, field, ',');
        }
        ASSERT_EQ(p.range, std::stof(field)) << i;
    }
    EXPECT_TRUE(multiple) << "the beam's rings split on edges: some pulses give several returns";
}

}  // namespace
}  // namespace beamtrace
