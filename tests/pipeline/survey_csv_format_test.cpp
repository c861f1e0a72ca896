// points.csv numbers read well: coordinates at the LAS scale's decimals (the LAS file's values),
// times without an exponent, scan angles in 0.006 degree steps, no "-0".
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> fields_of(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) {
        out.push_back(f);
    }
    return out;
}

std::size_t decimals(const std::string& f) {
    const auto dot = f.find('.');
    return dot == std::string::npos ? 0 : f.size() - dot - 1;
}

TEST(SurveyCsvFormat, NumbersAreTheLasValuesWithoutNoiseDigitsExponentsOrNegativeZero) {
    test::TempDir dir;
    const auto r =
        test::run_command(std::string(BEAMTRACE_CLI_PATH) + " survey " + BEAMTRACE_EXAMPLES_DIR +
                          "/surveys/airborne_line_physics.yaml --quiet --output '" +
                          (dir / "out").string() + "' 2>&1");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::stringstream csv(test::read_file(dir / "out" / "points.csv"));
    std::string line;
    std::getline(csv, line);
    ASSERT_EQ(line.rfind("x,y,z,gps_time,range_m,", 0), 0u);
    std::size_t rows = 0, small_times = 0;
    while (std::getline(csv, line)) {
        const auto f = fields_of(line);
        ASSERT_EQ(f.size(), 12u) << line;
        for (const auto& v : f) {
            ASSERT_EQ(v.find_first_of("eE"), std::string::npos) << line;
            ASSERT_NE(v, "-0") << line;
        }
        for (int k = 0; k < 3; ++k) {
            ASSERT_LE(decimals(f[static_cast<std::size_t>(k)]), 3u) << line;  // 1 mm
        }
        const double angle = std::stod(f[8]);
        ASSERT_NEAR(angle / 0.006, std::round(angle / 0.006), 1e-6) << line;
        small_times += std::stod(f[3]) > 0 && std::stod(f[3]) < 1e-4 ? 1 : 0;
        ++rows;
    }
    EXPECT_GT(rows, 100000u);
    EXPECT_GT(small_times, 0u);  // 0.00001 s and the like: written without an exponent
}

}  // namespace
}  // namespace beamtrace
