#include <gtest/gtest.h>

#include <numbers>

#include "beamtrace/core/angle_text.hpp"
#include "beamtrace/core/camera_pose.hpp"
#include "beamtrace/core/error.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(AngleText, ConvertsExplicitUnitsToTheKeysUnit) {
    EXPECT_EQ(parse_angle("60", AngleUnit::deg)->value, 60.0);
    EXPECT_FALSE(parse_angle("60", AngleUnit::deg)->explicit_unit);
    EXPECT_NEAR(parse_angle("60deg", AngleUnit::rad)->value, kPi / 3, 1e-15);
    EXPECT_TRUE(parse_angle("60deg", AngleUnit::rad)->explicit_unit);
    EXPECT_NEAR(parse_angle(" -1.5707963267948966 rad ", AngleUnit::deg)->value, -90.0, 1e-12);
    EXPECT_EQ(parse_angle("1.05rad", AngleUnit::rad)->value, 1.05);
    EXPECT_EQ(parse_angle("+45\xC2\xB0", AngleUnit::deg)->value, 45.0);
    for (const char* bad : {"", "deg", "60 degrees", "60radx", "1,5", "nan", "inf rad", "6 0"}) {
        EXPECT_FALSE(parse_angle(bad, AngleUnit::deg).has_value()) << bad;
    }
}

TEST(AngleText, RadianLookalikesAreMultiplesOfPiOverTwelveFromPiOverSix) {
    EXPECT_EQ(*radian_lookalike(-1.5708), "-\xCF\x80/2");
    EXPECT_EQ(*radian_lookalike(3.14), "\xCF\x80");
    EXPECT_EQ(*radian_lookalike(2 * kPi), "2\xCF\x80");
    EXPECT_EQ(*radian_lookalike(1.0472), "\xCF\x80/3");
    EXPECT_EQ(*radian_lookalike(4.18879), "4\xCF\x80/3");
    EXPECT_EQ(*radian_lookalike(0.5236), "\xCF\x80/6");
    for (const double deg : {0.0, 0.26, 1.0, 1.5, 1.575, 3.0, 3.145, 6.3, 90.0, -30.0, 0.005}) {
        EXPECT_FALSE(radian_lookalike(deg).has_value()) << deg;
    }
    const std::string msg = radian_lookalike_message(-1.5708, "-\xCF\x80/2");
    EXPECT_NE(msg.find("write -90 (degrees)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("-1.5708rad"), std::string::npos) << msg;
    EXPECT_NE(msg.find("-1.5708deg"), std::string::npos) << msg;
}

TEST(AngleText, OptionsAndCameraPosesTakeUnits) {
    EXPECT_NEAR(parse_angle_option("60deg", "--hfov", AngleUnit::rad), kPi / 3, 1e-15);
    EXPECT_THROW((void)parse_angle_option("sixty", "--hfov", AngleUnit::rad), ConfigError);
    const Vec3d v = parse_angle_vec3("0, -90deg ,0.25", "--orientation", AngleUnit::rad);
    EXPECT_EQ(v.x, 0.0);
    EXPECT_NEAR(v.y, -kPi / 2, 1e-15);
    EXPECT_EQ(v.z, 0.25);
    EXPECT_THROW((void)parse_angle_vec3("0,1", "--orientation", AngleUnit::rad), ConfigError);
    EXPECT_THROW((void)parse_angle_vec3("0,1,2,3", "--orientation", AngleUnit::rad), ConfigError);
    EXPECT_TRUE(radians_beyond_turn_warning(6.28, "--x").empty());
    EXPECT_FALSE(radians_beyond_turn_warning(-90, "--x").empty());

    const CameraPose p = parse_camera_pose("1,2,3,0.5rad,-30deg", "--camera").pose;
    EXPECT_NEAR(p.yaw_deg, 28.64788975654116, 1e-12);
    EXPECT_EQ(p.pitch_deg, -30.0);
    EXPECT_THROW((void)parse_camera_pose("1deg,2,3,0,0", "--camera"), ConfigError);  // metres
}

}  // namespace
}  // namespace beamtrace
