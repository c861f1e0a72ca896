// The LAS intensity scale of surveys: `physics.intensity.reference_range_m: auto` (the default)
// puts R_ref at half the survey's nominal range (the median first-hit range of a pilot), so a
// white Lambertian at the nominal range reads 65535 / 4; a number keeps R_ref as given; the
// airborne examples' terrain intensities span more than 8 bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "beamtrace/io/las_reader.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

/// One pulse straight down from the origin onto a white floor 40 m below, in vacuum.
std::string nadir_survey(const std::string& intensity) {
    return R"(scene: floor.yaml
scanner: {type: pinhole, width: 1, height: 1, hfov_deg: 1, vfov_deg: 1}
platform: {type: static, position_m: [0, 0, 0], rotate_deg: [0, -90, 0]}
physics:
  atmosphere: {enabled: false}
)" + intensity +
           "output: {trajectory_rate_hz: 0}\n";
}

SurveyResult run_in(const test::TempDir& dir, const std::string& yaml) {
    test::write_file(dir / "floor.yaml", R"(materials: [{name: white, reflectance: 1}]
parts: [{plane: {point_m: [0, 0, -40], normal: [0, 0, 1], size_m: 100}, material: white}]
)");
    test::write_file(dir / "survey.yaml", yaml);
    SurveyRunConfig run;
    run.output_dir = dir / "out";
    return run_survey(load_survey_spec(dir / "survey.yaml"), run);
}

TEST(SurveyIntensity, AutoReferenceRangeIsHalfTheNominalRange) {
    for (const std::string& intensity :
         {std::string(), std::string("  intensity: {reference_range_m: auto}\n")}) {
        test::TempDir dir;
        const SurveyResult r = run_in(dir, nadir_survey(intensity));
        ASSERT_TRUE(r.intensity_reference_range_m.has_value());
        EXPECT_TRUE(r.intensity_reference_auto);
        ASSERT_TRUE(r.nominal_range_m.has_value());
        EXPECT_NEAR(*r.nominal_range_m, 40.0, 1e-4);
        EXPECT_NEAR(*r.intensity_reference_range_m, 20.0, 1e-4);
        const auto points = read_las_points(dir / "out" / "points.las");
        ASSERT_EQ(points.size(), 1u);
        // The documented value: a white Lambertian at the nominal range reads 65535 / 4.
        EXPECT_NEAR(points[0].intensity, 65535 / 4.0, 2.0);
    }
}

TEST(SurveyIntensity, ExplicitReferenceRangeIsFullScaleForWhite) {
    test::TempDir dir;
    const SurveyResult r = run_in(dir, nadir_survey("  intensity: {reference_range_m: 40}\n"));
    EXPECT_FALSE(r.intensity_reference_auto);
    EXPECT_EQ(r.intensity_reference_range_m, 40.0);
    const auto points = read_las_points(dir / "out" / "points.las");
    ASSERT_EQ(points.size(), 1u);
    EXPECT_NEAR(points[0].intensity, 65535, 2.0);
}

/// The terrain returns (point source ID = part ID `part_id`) of the first `pulses` pulses of
/// example survey `name`, run as it is.
std::vector<std::uint16_t> terrain_intensities(const std::string& name, std::uint64_t pulses,
                                               int part_id, SurveyResult& result) {
    const std::filesystem::path file =
        std::filesystem::path(BEAMTRACE_EXAMPLES_DIR) / "surveys" / name;
    test::TempDir dir;
    SurveyRunConfig run;
    run.output_dir = dir / "out";
    run.max_pulses = pulses;
    result = run_survey(load_survey_spec(file), run);
    std::vector<std::uint16_t> out;
    for (const LasPoint& p : read_las_points(dir / "out" / "points.las")) {
        if (p.point_source_id == part_id) {
            out.push_back(p.intensity);
        }
    }
    return out;
}

// Acceptance: over the terrain of the airborne examples (150 m and 1.5 km), no detected return
// reads 0 and the intensities span at least 8 bits: max - min + 1 >= 256 levels, with at least
// 256 distinct values. (With the old 10 m reference range they read 0 to 2.)
TEST(SurveyIntensity, AirborneTerrainIntensitiesSpanEightBits) {
    struct Case {
        const char* name;
        int part_id;
        double altitude_m;
    };
    for (const Case& c : {Case{"airborne_line_physics.yaml", 1, 150.0},
                          Case{"airborne_srtm_divergence.yaml", 1, 1500.0}}) {
        SCOPED_TRACE(c.name);
        if (std::string(c.name).find("srtm") != std::string::npos) {
            BEAMTRACE_REQUIRE_FILE(test::shared_data("meshes/terrain/dem_hd.tif"));
        }
        SurveyResult r;
        const auto values = terrain_intensities(c.name, 20000, c.part_id, r);
        ASSERT_GT(values.size(), 10000u);
        ASSERT_TRUE(r.intensity_reference_auto);
        EXPECT_GT(*r.nominal_range_m, c.altitude_m * 0.8);
        EXPECT_LT(*r.nominal_range_m, c.altitude_m * 1.3);
        const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
        EXPECT_GT(*lo, 0);
        EXPECT_GE(*hi - *lo + 1, 256) << "min " << *lo << " max " << *hi;
        std::vector<std::uint16_t> distinct = values;
        std::sort(distinct.begin(), distinct.end());
        distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
        EXPECT_GE(distinct.size(), 256u);
        EXPECT_LT(*hi, 65535) << "the terrain does not saturate";
    }
}

}  // namespace
}  // namespace beamtrace
