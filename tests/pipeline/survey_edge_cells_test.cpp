// Targets smaller than a sub-ray's cell (physics/beam_divergence.hpp, "Edge cells"): a strip
// across the beam and the edge of a plane return the share of the pulse energy they cover, the
// Gaussian profile integrated over them, not the sum of the cells their sub-rays fall in.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kRange_m = 100.0;
constexpr double kDivergence_mrad = 2.0;
// The 1/e^2 radius of the footprint at kRange_m: W = R theta / 2.
constexpr double kFootprint_m = kRange_m * kDivergence_mrad * 1e-3 / 2.0;

/// A horizontal rectangle [x0, x1] x [-50, 50] at z = -kRange_m, as an OBJ.
std::string rectangle_obj(double x0, double x1) {
    const std::string z = std::to_string(-kRange_m);
    const auto v = [&](double x, double y) {
        return "v " + std::to_string(x) + " " + std::to_string(y) + " " + z + "\n";
    };
    return v(x0, -50) + v(x1, -50) + v(x1, 50) + v(x0, 50) + "f 1 2 3\nf 1 3 4\n";
}

/// A line scanner at the origin looking straight down, sweeping +-1e-4 deg (2 cm at 100 m's
/// footprint of 10 cm: the beam stays put), 200 pulses, every return's intensity on a linear
/// scale with a white Lambertian at kRange_m reading 65535.
std::string survey_yaml(int edge_samples) {
    return R"(scene: scene.yaml
scanner: {type: line, pulse_rate_hz: 2000, scan_rate_hz: 10, scan_angle_max_deg: 0.0001,
          duration_s: 0.1}
platform: {type: static, position_m: [0, 0, 0]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: )" +
           std::to_string(kDivergence_mrad) +
           ", rings: 2, edge_samples: " + std::to_string(edge_samples) + R"(}
  detection_threshold_w: 1.0e-12
  intensity: {reference_range_m: )" +
           std::to_string(kRange_m) + R"(, scale: linear}
  atmosphere: {enabled: false}
  returns: {mode: all, max: 5}
output: {trajectory_rate_hz: 0, preview: false}
)";
}

/// The mean intensity of the survey's points over the rectangle [x0, x1] (every pulse must give
/// exactly one return).
double mean_intensity(double x0, double x1, int edge_samples) {
    test::TempDir dir;
    test::write_file(dir / "rect.obj", rectangle_obj(x0, x1));
    test::write_file(dir / "scene.yaml", "parts:\n  - {mesh: rect.obj, material: default}\n");
    const auto points = test::run_and_read(survey_yaml(edge_samples), dir);
    EXPECT_EQ(points.size(), 200u);
    double sum = 0.0;
    for (const auto& p : points) {
        EXPECT_EQ(p.number_of_returns, 1);
        sum += p.intensity;
    }
    return points.empty() ? 0.0 : sum / static_cast<double>(points.size());
}

/// The share of a Gaussian beam of 1/e^2 radius W (per-axis sigma W / 2) falling on x0 < x < x1.
double gaussian_share(double x0, double x1) {
    const auto cdf = [](double x) { return 0.5 * std::erfc(-std::sqrt(2.0) * x / kFootprint_m); };
    return cdf(x1) - cdf(x0);
}

TEST(SurveyEdgeCells, AStripAcrossTheBeamReturnsTheShareOfTheEnergyItCovers) {
    const double full = mean_intensity(-50, 50, 3);
    ASSERT_GT(full, 20000.0);  // reflectance 0.5 at the reference range: about 32768
    // A strip 0.6 W wide (a 6 cm bar at 100 m) under the centre of the beam: 45 % of it.
    const double hw = 0.3 * kFootprint_m;
    const double expected = gaussian_share(-hw, hw);
    const double refined = mean_intensity(-hw, hw, 3) / full;
    EXPECT_NEAR(refined, expected, 0.05 * expected);
    // Without edge samples the sub-rays on the strip count their whole cells: 21 % short.
    const double cells = mean_intensity(-hw, hw, 0) / mean_intensity(-50, 50, 0);
    EXPECT_GT(std::abs(cells - expected), 0.15 * expected) << cells;
}

TEST(SurveyEdgeCells, TheEdgeOfAPlaneReturnsTheShareOfTheEnergyItCovers) {
    const double full = mean_intensity(-50, 50, 3);
    const double full_cells = mean_intensity(-50, 50, 0);
    // The plane's edge 0.1 W and 0.3 W off the beam's centre, on either side: 27 to 73 % of the
    // beam falls on it. Without edge samples the share is 16 to 24 % off.
    for (const double x0 : {0.1 * kFootprint_m, 0.3 * kFootprint_m, -0.3 * kFootprint_m}) {
        const double expected = gaussian_share(x0, 50);
        EXPECT_NEAR(mean_intensity(x0, 50, 3) / full, expected, 0.05 * expected) << x0;
        if (x0 > 0) {
            const double cells = mean_intensity(x0, 50, 0) / full_cells;
            EXPECT_GT(std::abs(cells - expected), 0.15 * expected) << x0 << " " << cells;
        }
    }
}

TEST(SurveyEdgeCells, AStripInFrontOfAWallSharesThePulseWithIt) {
    const double full = mean_intensity(-50, 50, 3);
    test::TempDir dir;
    const double hw = 0.3 * kFootprint_m;
    test::write_file(dir / "strip.obj", rectangle_obj(-hw, hw));
    test::write_file(dir / "wall.obj", rectangle_obj(-50, 50));
    // The wall 3 m behind the strip: two echoes, each labelled with what it came from.
    test::write_file(dir / "scene.yaml",
                     "parts:\n  - {mesh: strip.obj, label: 9}\n"
                     "  - {mesh: wall.obj, label: 2, transform: {translate_m: [0, 0, -3]}}\n");
    const auto points = test::run_and_read(survey_yaml(3), dir);
    ASSERT_EQ(points.size(), 400u);
    double strip = 0.0, wall = 0.0;
    for (std::size_t i = 0; i < points.size(); i += 2) {
        ASSERT_EQ(points[i].number_of_returns, 2);
        EXPECT_EQ(points[i].classification, 9);
        EXPECT_NEAR(points[i].z, -kRange_m, 0.01);
        EXPECT_EQ(points[i + 1].classification, 2);
        EXPECT_NEAR(points[i + 1].z, -kRange_m - 3.0, 0.01);
        strip += points[i].intensity / full / 200.0;
        wall += points[i + 1].intensity / full / 200.0;
    }
    const double share = gaussian_share(-hw, hw);
    EXPECT_NEAR(strip, share, 0.05 * share);
    // The rest of the beam on the wall, at 103 m: (100 / 103)^2 as bright.
    const double behind = (1.0 - share) * std::pow(kRange_m / (kRange_m + 3.0), 2);
    EXPECT_NEAR(wall, behind, 0.05 * behind);
}

/// The points of dir/out/points.las, every field of the records as our reader decodes them.
std::vector<std::string> records(const test::TempDir& dir) {
    std::vector<std::string> out;
    for (const auto& p : read_las_points(dir / "out" / "points.las")) {
        out.push_back(std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) +
                      " " + std::to_string(p.intensity) + " " + std::to_string(p.gps_time) + " " +
                      std::to_string(p.return_number) + "/" + std::to_string(p.number_of_returns) +
                      " " + std::to_string(p.classification) + " " +
                      std::to_string(p.point_source_id));
    }
    return out;
}

TEST(SurveyEdgeCells, AFullyCoveredBeamIsTracedAsBeforeAndEdgesAtAnyThreadCount) {
    // Every sub-ray on one surface: no cell is an edge, the output is that of edge_samples: 0.
    test::TempDir dir;
    test::write_file(dir / "rect.obj", rectangle_obj(-50, 50));
    test::write_file(dir / "scene.yaml", "parts:\n  - {mesh: rect.obj}\n");
    test::run_survey_in(survey_yaml(3), dir, 2, 1 << 16, 1);
    const auto refined = records(dir);
    ASSERT_EQ(refined.size(), 200u);
    std::filesystem::remove_all(dir / "out");
    test::run_survey_in(survey_yaml(0), dir, 2, 1 << 16, 1);
    EXPECT_TRUE(refined == records(dir));
    // Edges: the same bytes on 1 and 2 threads, and in chunks of one block.
    test::write_file(dir / "rect.obj", rectangle_obj(-0.02, 0.02));
    std::filesystem::remove_all(dir / "out");
    test::run_survey_in(survey_yaml(3), dir, 1, 1 << 16, 1);
    const std::string one = test::read_file(dir / "out" / "points.las");
    std::filesystem::remove_all(dir / "out");
    test::run_survey_in(survey_yaml(3), dir, 2, 1024, 1);
    EXPECT_TRUE(one == test::read_file(dir / "out" / "points.las"));
}

}  // namespace
}  // namespace beamtrace
