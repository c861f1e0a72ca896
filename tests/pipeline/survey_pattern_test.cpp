// A patterned material gives patterned survey intensities: the survey's physics evaluates the
// material's albedo pattern at each hit, on the same surface as `render` (a plane's axes, a
// sphere's local frame). Each test runs the scene twice, patterned and uniform, from the same
// pose without noise: every point's intensity ratio is the ratio of the reflectances there.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "beamtrace/core/quat.hpp"
#include "pipeline/survey_test_support.hpp"
#include "test_support.hpp"

namespace beamtrace {
namespace {

constexpr double kBase = 0.8;
constexpr double kAlternate = 0.2;

/// A row of 9 pixels across `hfov_deg` looking straight down from `position_m`, no atmosphere;
/// a white panel at 10 m is full scale.
std::string nadir_row(int hfov_deg, const std::string& position_m) {
    return "scene: scene.yaml\nscanner: {type: scan, width: 9, height: 1, hfov_deg: " +
           std::to_string(hfov_deg) +
           ", vfov_deg: 1}\nplatform: {type: static, position_m: " + position_m +
           R"(, rotate_deg: [0, -90, 0]}
physics:
  atmosphere: {enabled: false}
  intensity: {reference_range_m: 10}
output: {trajectory_rate_hz: 0}
)";
}

std::vector<LasPoint> survey(const std::string& material, const std::string& part,
                             const std::string& row) {
    test::TempDir dir;
    test::write_file(dir / "scene.yaml",
                     "materials:\n  - " + material + "\nparts:\n  - " + part + "\n");
    return test::run_and_read(row, dir);
}

/// The distance of x to the nearest integer.
double off_integer(double x) {
    return std::fabs(x - std::round(x));
}

TEST(SurveyPattern, CheckeredFloorGivesCheckeredIntensities) {
    const std::string part =
        "{plane: {point_m: [0, 0, -10], normal: [0, 0, 1], size_m: 100}, material: m}";
    const std::string row = nadir_row(60, "[0.3, 0.5, 0]");
    const auto uniform = survey("{name: m, reflectance: 0.8}", part, row);
    const auto checker =
        survey("{name: m, reflectance: 0.8, pattern: {kind: checker, size_m: 1, reflectance: 0.2}}",
               part, row);
    ASSERT_EQ(uniform.size(), 9u);
    ASSERT_EQ(checker.size(), 9u);
    int base = 0, alternate = 0;
    for (std::size_t i = 0; i < 9; ++i) {
        const LasPoint& p = checker[i];
        ASSERT_NEAR(p.x, uniform[i].x, 1e-9);
        ASSERT_NEAR(p.y, uniform[i].y, 1e-9);
        // The plane's axes for normal +z are u = -y and w = x (make_square): cells of 1 m.
        ASSERT_GT(off_integer(p.x), 0.01) << "a point on a cell edge";
        ASSERT_GT(off_integer(p.y), 0.01) << "a point on a cell edge";
        const auto k = static_cast<long>(std::floor(-p.y) + std::floor(p.x));
        const bool odd = k % 2 != 0;
        const double want = (odd ? kAlternate : kBase) / kBase;
        EXPECT_NEAR(p.intensity / double(uniform[i].intensity), want, 1e-3) << p.x << " " << p.y;
        (odd ? alternate : base) += 1;
    }
    EXPECT_GT(base, 0);
    EXPECT_GT(alternate, 0);
}

TEST(SurveyPattern, StripedBallGivesStripedIntensities) {
    // The beach ball: 8 gores about its local z axis, turned 45 degrees about z (one gore) so
    // that its attitude matters; an exact sphere of radius 5 centred at (3, -2, 1).
    const std::string part =
        "{sphere: {center_m: [0, 0, 0], radius_m: 5, exact: true}, material: m, "
        "transform: {translate_m: [3, -2, 1], rotate_deg: [0, 0, 45]}}";
    const std::string row = nadir_row(20, "[4.3, -1.2, 21]");  // off the top: many longitudes
    const auto uniform = survey("{name: m, reflectance: 0.8}", part, row);
    const auto striped =
        survey("{name: m, reflectance: 0.8, pattern: {kind: stripes, count: 8, reflectance: 0.2}}",
               part, row);
    ASSERT_EQ(uniform.size(), 9u) << "every ray should meet the ball";
    ASSERT_EQ(striped.size(), 9u);
    const Quat q = Quat::from_rpy({0, 0, std::numbers::pi / 4});
    const Vec3d centre{3, -2, 1};
    int base = 0, alternate = 0, turned = 0;
    for (std::size_t i = 0; i < 9; ++i) {
        const LasPoint& p = striped[i];
        const Vec3d local = q.conjugate().rotate(Vec3d{p.x, p.y, p.z} - centre);
        const auto gore = [](const Vec3d& v) {
            const double s = (std::atan2(v.y, v.x) + std::numbers::pi) / (std::numbers::pi / 4);
            EXPECT_GT(off_integer(s), 1e-3) << "a point on a gore's edge";
            return static_cast<long>(std::floor(s));
        };
        const bool odd = gore(local) % 2 != 0;
        turned += (gore(Vec3d{p.x, p.y, p.z} - centre) % 2 != 0) != odd ? 1 : 0;
        const double want = (odd ? kAlternate : kBase) / kBase;
        EXPECT_NEAR(p.intensity / double(uniform[i].intensity), want, 1e-3) << p.x << " " << p.y;
        (odd ? alternate : base) += 1;
    }
    EXPECT_GT(base, 0);
    EXPECT_GT(alternate, 0);
    EXPECT_GT(turned, 0) << "the row should see the turn of the stripes";
}

}  // namespace
}  // namespace beamtrace
