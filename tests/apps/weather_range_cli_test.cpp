// `beamtrace weather-range`: its CSV is the library's solver (max_detection_range_in_fog_m) with
// a survey's physics, row by row; its plot is a PNG with one curve per reflectance; bad options
// are one-line errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "beamtrace/io/png_reader.hpp"
#include "beamtrace/physics/weather.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

namespace fs = std::filesystem;

const std::string kSurvey = std::string(BEAMTRACE_EXAMPLES_DIR) + "/surveys/weather_clear.yaml";

test::RunResult weather_range(const std::string& flags) {
    return test::run_command(std::string(BEAMTRACE_CLI_PATH) + " weather-range " + flags);
}

struct Row {
    double reflectance = 0.0, mor_m = 0.0, range_m = 0.0;
};

std::vector<Row> read_rows(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "reflectance,mor_m,max_range_m");
    std::vector<Row> rows;
    while (std::getline(in, line)) {
        Row r;
        char* end = nullptr;
        r.reflectance = std::strtod(line.c_str(), &end);
        r.mor_m = std::strtod(end + 1, &end);
        r.range_m = std::strtod(end + 1, &end);
        EXPECT_EQ(*end, '\0') << line;
        rows.push_back(r);
    }
    return rows;
}

TEST(WeatherRangeCli, CsvIsTheSolverWithTheSurveysPhysics) {
    test::TempDir dir;
    const fs::path csv = dir / "range.csv";
    const auto r = weather_range("--survey '" + kSurvey +
                                 "' --reflectance 0.1 0.5 --mor-min 20 --mor-max 2000 "
                                 "--points 5 --csv '" +
                                 csv.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const std::vector<Row> rows = read_rows(test::read_file(csv));
    ASSERT_EQ(rows.size(), 10u);
    const PhysicsConfig p = load_survey_spec(kSurvey).physics.value();
    ASSERT_EQ(p.radiometry.peak_power_w, 30.0);  // the survey's, not the defaults
    const double mors[] = {20.0, 63.245553203367585, 200.0, 632.45553203367592, 2000.0};
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const Row& row = rows[i];
        EXPECT_EQ(row.reflectance, i < 5 ? 0.1 : 0.5);
        EXPECT_NEAR(row.mor_m, mors[i % 5], 1e-12 * mors[i % 5]) << i;
        EXPECT_EQ(row.range_m, max_detection_range_in_fog_m(p.radiometry, p.atmosphere,
                                                            row.reflectance, row.mor_m))
            << i;
    }
    // Without --csv or --output the table goes to standard output, with the defaults' physics.
    const auto plain = weather_range("--reflectance 0.5 --mor-min 100 --mor-max 200 --points 2");
    ASSERT_EQ(plain.exit_code, 0) << plain.out;
    const std::vector<Row> defaults = read_rows(plain.out);
    ASSERT_EQ(defaults.size(), 2u);
    const PhysicsConfig d;
    EXPECT_EQ(defaults[1].range_m,
              max_detection_range_in_fog_m(d.radiometry, d.atmosphere, 0.5, defaults[1].mor_m));
}

/// The mean row of the pixels of colour `c` in `image`; -1 when there are none.
double mean_row_of(const RgbImage& image, std::array<std::uint8_t, 3> c) {
    double sum = 0.0;
    std::size_t n = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::size_t i = 3 * (static_cast<std::size_t>(y) * image.width + x);
            if (image.rgb[i] == c[0] && image.rgb[i + 1] == c[1] && image.rgb[i + 2] == c[2]) {
                sum += y;
                ++n;
            }
        }
    }
    return n == 0 ? -1.0 : sum / static_cast<double>(n);
}

TEST(WeatherRangeCli, PlotsOneCurvePerReflectance) {
    test::TempDir dir;
    const fs::path png = dir / "range.png";
    const auto r = weather_range("--reflectance 0.1 0.5 --output '" + png.string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const RgbImage image = read_png_rgb8(png);
    EXPECT_EQ(image.width, 720);
    EXPECT_EQ(image.height, 440);
    // The first curve (0.1) in blue, the second (0.5) in red, above it (rows count down).
    const double low = mean_row_of(image, {31, 119, 180});
    const double high = mean_row_of(image, {214, 39, 40});
    ASSERT_GT(low, 0.0);
    ASSERT_GT(high, 0.0);
    EXPECT_LT(high, low);
}

TEST(WeatherRangeCli, BadOptionsAreOneLineErrors) {
    for (const char* flags : {"--reflectance 0", "--reflectance 1.5", "--mor-min 0",
                              "--mor-min 500 --mor-max 100", "--points 1"}) {
        const auto r = weather_range(flags);
        EXPECT_EQ(r.exit_code, 2) << flags << ": " << r.out;
        EXPECT_NE(r.out.find("beamtrace: error: weather-range: "), std::string::npos)
            << flags << ": " << r.out;
    }
}

}  // namespace
}  // namespace beamtrace
