// Surveys with the physics block: intensity from the range equation, multiple returns from beam
// divergence at a step edge and in a tree, and determinism with noise at any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>

#include "beamtrace/core/error.hpp"
#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/physics/material_library.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

using test::run_and_read;

// Two horizontal planes meeting at x = 0: z = -20 for x < 0, z = -21 for x > 0.
constexpr const char* kStep = R"(parts:
  - {plane: {point_m: [-50, 0, -20], normal: [0, 0, 1], size_m: 100}, label: 2}
  - {plane: {point_m: [50, 0, -21], normal: [0, 0, 1], size_m: 100}, label: 6}
)";

std::string step_survey(double x_m) {
    return R"(scene: step.yaml
scanner: {type: pinhole, width: 1, height: 1, hfov_deg: 1, vfov_deg: 1}
platform: {type: static, position_m: [)" +
           std::to_string(x_m) + R"(, 0, 0], rotate_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 20, rings: 2}
  atmosphere: {enabled: false}
output: {trajectory_rate_hz: 0}
)";
}

/// A row of 9 pixels across `hfov_deg` looking straight down from `position_m`, with
/// intensities (a white panel at 10 m is full scale) and no atmosphere.
std::string nadir_row_survey(const std::string& scene, int hfov_deg,
                             const std::string& position_m) {
    return "scene: " + scene +
           "\nscanner: {type: scan, width: 9, height: 1, hfov_deg: " + std::to_string(hfov_deg) +
           ", vfov_deg: 1}\nplatform: {type: static, position_m: " + position_m +
           R"(, rotate_deg: [0, -90, 0]}
physics:
  atmosphere: {enabled: false}
  intensity: {reference_range_m: 10}
output: {trajectory_rate_hz: 0}
)";
}

TEST(SurveyPhysics, StepEdgeStraddledByTheFootprintGivesTwoReturns) {
    test::TempDir dir;
    test::write_file(dir / "step.yaml", kStep);
    // The 20 mrad beam is 0.4 m wide at 20 m: centred on the edge it sees both planes.
    const auto two = run_and_read(step_survey(0.0), dir);
    ASSERT_EQ(two.size(), 2u);
    EXPECT_EQ(two[0].return_number, 1);
    EXPECT_EQ(two[1].return_number, 2);
    EXPECT_EQ(two[0].number_of_returns, 2);
    EXPECT_EQ(two[1].number_of_returns, 2);
    EXPECT_NEAR(two[0].z, -20.0, 0.02);
    EXPECT_NEAR(two[1].z, -21.0, 0.02);
    EXPECT_EQ(two[0].classification, 2);
    EXPECT_EQ(two[1].classification, 6);
    EXPECT_GT(two[0].intensity, 0);
    // Away from the edge: one plane, one return.
    test::TempDir dir2;
    test::write_file(dir2 / "step.yaml", kStep);
    const auto one = run_and_read(step_survey(-5.0), dir2);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0].return_number, 1);
    EXPECT_EQ(one[0].number_of_returns, 1);
    EXPECT_NEAR(one[0].z, -20.0, 0.02);
    EXPECT_GT(one[0].intensity, two[0].intensity) << "the whole beam on one plane is stronger";
}

TEST(SurveyPhysics, WaveformSidecarHoldsBothEchoesOfTheStepEdge) {
    test::TempDir dir;
    test::write_file(dir / "step.yaml", kStep);
    std::string yaml = step_survey(0.0);
    yaml.replace(yaml.find("  atmosphere:"), 0,
                 "  waveform: {pulse_fwhm_ns: 2, bin_ns: 0.25, keep: true}\n");
    const auto points = run_and_read(yaml, dir);
    ASSERT_EQ(points.size(), 2u);
    const std::string bytes = test::read_file(dir / "out" / "waveforms.bin");
    ASSERT_GE(bytes.size(), 32u + 72u + 4u);
    EXPECT_EQ(bytes.substr(0, 8), "BTWAVE01");
    const auto get = [&](std::size_t at, auto value) {
        std::memcpy(&value, bytes.data() + at, sizeof value);
        return value;
    };
    EXPECT_EQ(get(8, std::uint32_t{}), 1u);
    EXPECT_DOUBLE_EQ(get(16, double{}), 0.25);
    EXPECT_DOUBLE_EQ(get(24, double{}), 2.0);
    // One record: pulse 0, time, origin, axis, first bin, count, samples.
    EXPECT_EQ(get(32, std::uint64_t{}), 0u);
    EXPECT_DOUBLE_EQ(get(32 + 8 + 8 * 6, double{}), -1.0);  // axis z: straight down
    const auto first_bin = get(32 + 64, std::int64_t{});
    const auto n = get(32 + 72, std::uint32_t{});
    ASSERT_EQ(bytes.size(), 32u + 76u + 4u * n);
    std::vector<float> w(n);
    std::memcpy(w.data(), bytes.data() + 32 + 76, 4u * n);
    // Local maxima above a tenth of the strongest: the two planes' echoes, at the round-trip
    // times of 20 m and 21 m.
    const float top = *std::max_element(w.begin(), w.end());
    std::vector<double> peaks_m;
    for (std::size_t k = 1; k + 1 < n; ++k) {
        if (w[k] > 0.1f * top && w[k] >= w[k - 1] && w[k] > w[k + 1]) {
            const double t_ns =
                static_cast<double>(first_bin + static_cast<std::int64_t>(k)) * 0.25;
            peaks_m.push_back(t_ns * 1e-9 * 299792458.0 / 2.0);
        }
    }
    ASSERT_EQ(peaks_m.size(), 2u);
    EXPECT_NEAR(peaks_m[0], 20.0, 0.04);
    EXPECT_NEAR(peaks_m[1], 21.0, 0.04);
}

TEST(SurveyPhysics, LambertianIntensityFollowsCosineOverRangeSquared) {
    test::TempDir dir;
    test::write_file(dir / "floor.yaml", R"(parts:
  - {plane: {point_m: [0, 0, -10], normal: [0, 0, 1], size_m: 400}}
)");
    // A row of 9 pixels across 120 degrees, looking down from 10 m: pixel k sees the floor at
    // angle theta from the vertical, range 10 / cos(theta) and incidence theta, so the power is
    // proportional to cos(theta) / R^2 = cos^3(theta) / 100.
    const auto points = run_and_read(nadir_row_survey("floor.yaml", 120, "[0, 0, 0]"), dir);
    ASSERT_EQ(points.size(), 9u);
    const LasPoint* centre = nullptr;
    for (const auto& p : points) {
        if (std::hypot(p.x, p.y) < 1e-6) {
            centre = &p;
        }
    }
    ASSERT_NE(centre, nullptr);
    // A white panel at 10 m is full scale; this floor's albedo is 0.5.
    EXPECT_NEAR(centre->intensity, 0.5 * 65535, 2.0);
    for (const auto& p : points) {
        const double r = std::sqrt(p.x * p.x + p.y * p.y + 100.0);
        const double cos_theta = 10.0 / r;
        const double want = centre->intensity * cos_theta * 100.0 / (r * r);
        EXPECT_NEAR(p.intensity, want, 0.01 * want + 1.0) << p.x << " " << p.y;
    }
}

TEST(SurveyPhysics, ExactSphereReturnsLieOnItAndFollowItsNormal) {
    test::TempDir dir;
    test::write_file(dir / "ball.yaml", R"(parts:
  - {sphere: {center_m: [3, -2, 1], radius_m: 5, exact: true}, label: 9}
)");
    // A row of 9 pixels across 28 degrees from 20 m above the centre: every ray meets the
    // sphere, at incidence angle acos(-d . n) with n the sphere's outward normal at the point.
    const auto points = run_and_read(nadir_row_survey("ball.yaml", 28, "[3, -2, 21]"), dir);
    ASSERT_EQ(points.size(), 9u);
    const Vec3d centre{3, -2, 1};
    const LasPoint* top = nullptr;
    for (const auto& p : points) {
        EXPECT_NEAR(length(Vec3d{p.x, p.y, p.z} - centre), 5.0, 1e-3);
        EXPECT_EQ(p.classification, 9);
        if (std::hypot(p.x - centre.x, p.y - centre.y) < 1e-6) {
            top = &p;
        }
    }
    ASSERT_NE(top, nullptr);
    EXPECT_NEAR(top->z, 6.0, 1e-3);
    bool oblique = false;
    for (const auto& p : points) {
        const Vec3d at = Vec3d{p.x, p.y, p.z} - centre;
        const Vec3d to_sensor = Vec3d{0, 0, 20} - at;
        const double range = length(to_sensor);
        const double cos_incidence = dot(to_sensor, at) / (range * 5.0);
        const double want = top->intensity * cos_incidence * (15.0 * 15.0) / (range * range);
        EXPECT_NEAR(p.intensity, want, 0.01 * want + 1.0) << p.x << " " << p.y;
        oblique = oblique || cos_incidence < 0.6;
    }
    EXPECT_TRUE(oblique) << "the row should reach the sphere's flank";
}

TEST(SurveyPhysics, LibraryMaterialsResolveAtTheSurveyWavelength) {
    test::TempDir dir;
    // Grass is bright at 1064 nm and dark at 1550 nm (leaf water); the survey looks straight
    // down at it from 10 m, its nominal range, where a white panel reads a quarter of full scale
    // (the auto reference range is half the nominal range).
    test::write_file(dir / "lawn.yaml", R"(materials:
  - {name: lawn, library: grass}
parts:
  - {plane: {point_m: [0, 0, -10], normal: [0, 0, 1], size_m: 40}, material: lawn}
)");
    const auto survey = [](int wavelength_nm) {
        return R"(scene: lawn.yaml
scanner: {type: pinhole, width: 1, height: 1, hfov_deg: 1, vfov_deg: 1}
platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, -90, 0]}
physics: {wavelength_nm: )" +
               std::to_string(wavelength_nm) + R"(, atmosphere: {enabled: false}}
output: {trajectory_rate_hz: 0}
)";
    };
    const auto near_ir = run_and_read(survey(1064), dir);
    ASSERT_EQ(near_ir.size(), 1u);
    const auto lib = library_material("grass", 1064.0);
    ASSERT_TRUE(lib.has_value());
    EXPECT_NEAR(near_ir[0].intensity, lib->reflectance * 65535 / 4, 2.0);
    test::TempDir dir2;
    test::write_file(dir2 / "lawn.yaml", test::read_file(dir / "lawn.yaml"));
    const auto swir = run_and_read(survey(1550), dir2);
    ASSERT_EQ(swir.size(), 1u);
    EXPECT_LT(swir[0].intensity, near_ir[0].intensity * 7 / 10);
    // An unknown library name is refused before anything is written.
    test::TempDir dir3;
    test::write_file(dir3 / "lawn.yaml", R"(materials: [{name: lawn, library: astroturf}]
parts: [{plane: {point_m: [0, 0, -10], normal: [0, 0, 1], size_m: 40}, material: lawn}]
)");
    try {
        (void)run_and_read(survey(1064), dir3);
        FAIL() << "expected a ConfigError";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown library material 'astroturf'"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(dir3 / "out" / "points.las"));
}

TEST(SurveyPhysics, TreeGivesMultipleReturns) {
    const auto tree = test::shared_mesh("vegetation/white_birch.obj");
    BEAMTRACE_REQUIRE_FILE(tree);
    test::TempDir dir;
    test::write_file(dir / "tree.yaml", "parts:\n  - {mesh: " + tree.string() +
                                            ", label: 5}\n"
                                            "  - {plane: {point_m: [0, 0, 0], normal: [0, 0, "
                                            "1], size_m: 60}, label: 2}\n");
    // A line scanner 100 m above the tree with a 3 mrad beam (30 cm footprint).
    const auto points = run_and_read(R"(scene: tree.yaml
scanner: {type: line, pulse_rate_hz: 20000, scan_rate_hz: 100, scan_angle_max_deg: 4, waveform: sawtooth, duration_s: 0.4}
platform: {type: legs, speed_mps: 30, waypoints_m: [[-6, 0, 100], [6, 0, 100]]}
mount: {boresight_deg: [0, -90, 0]}
physics:
  beam: {divergence_mrad: 3, rings: 2}
  returns: {mode: all, max: 5}
output: {trajectory_rate_hz: 0}
)",
                                     dir);
    ASSERT_GT(points.size(), 7000u);
    std::map<int, std::size_t> by_count;
    std::size_t multi_first_on_tree = 0, multi_last_on_ground = 0, multi_pulses = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const LasPoint& p = points[i];
        ASSERT_GE(p.return_number, 1);
        ASSERT_LE(p.return_number, p.number_of_returns);
        ASSERT_LE(p.number_of_returns, 5);
        if (p.return_number == 1) {
            ++by_count[p.number_of_returns];
            if (p.number_of_returns > 1) {
                ++multi_pulses;
                multi_first_on_tree += p.classification == 5 ? 1 : 0;
                // The returns of a pulse are consecutive, nearest first.
                ASSERT_LT(i + p.number_of_returns - 1, points.size());
                for (std::size_t r = 1; r < p.number_of_returns; ++r) {
                    ASSERT_EQ(points[i + r].return_number, r + 1);
                    ASSERT_EQ(points[i + r].gps_time, p.gps_time);
                    ASSERT_LT(points[i + r].z, points[i + r - 1].z);
                }
                const LasPoint& last = points[i + p.number_of_returns - 1];
                multi_last_on_ground += std::abs(last.z) < 0.05 ? 1 : 0;
            }
        }
    }
    // Plausible: a good share of the pulses through the crown split, a few into 3 or more; the
    // first of a split pulse is on the tree and the last often on the ground.
    const std::size_t pulses = multi_pulses + by_count[1];
    EXPECT_EQ(pulses, 8000u) << "every pulse hits the tree or the ground";
    EXPECT_GT(multi_pulses, pulses * 15 / 100);
    EXPECT_LT(multi_pulses, pulses * 75 / 100);
    EXPECT_GT(by_count[3], 0u);
    EXPECT_GT(by_count[4], 0u);
    EXPECT_GT(multi_first_on_tree, multi_pulses * 9 / 10);
    EXPECT_GT(multi_last_on_ground, multi_pulses / 10);
}

TEST(SurveyPhysics, NoiseAndReturnsAreIdenticalForAnyThreadCount) {
    test::TempDir a, b;
    const std::string yaml = R"(scene: demo
scanner: {type: rotating, preset: vlp16, duration_s: 0.05}
platform: {type: legs, speed_mps: 10, waypoints_m: [[-10, -10, 2], [10, -10, 3]]}
physics:
  beam: {divergence_mrad: 3, rings: 1}
  noise: {range_sigma_m: 0.02, angle_jitter_mrad: 0.1, position_sigma_m: 0.01, dropout_probability: 0.05}
output: {csv: true}
)";
    const auto pa = run_and_read(yaml, a, 1, 1 << 16);
    const auto pb = run_and_read(yaml, b, 2, 777);
    ASSERT_GT(pa.size(), 1000u);
    EXPECT_EQ(test::read_file(a / "out" / "points.las"), test::read_file(b / "out" / "points.las"));
    const std::string csv = test::read_file(a / "out" / "points.csv");
    EXPECT_EQ(csv, test::read_file(b / "out" / "points.csv"));
    EXPECT_NE(csv.substr(0, csv.find('\n')).find(",intensity,return_number,number_of_returns"),
              std::string::npos);
}

}  // namespace
}  // namespace beamtrace
