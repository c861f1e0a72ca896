// ScanJobConfig as `beamtrace scan` fills it: the sensor options over the default or demo sensor,
// the k-d tree rules, and the "x,y,z" text of --position and --orientation.
#include <gtest/gtest.h>

#include "beamtrace/core/error.hpp"
#include "beamtrace/core/vec3_text.hpp"
#include "beamtrace/pipeline/demo_sensor.hpp"
#include "beamtrace/pipeline/scan_job.hpp"

namespace bt = beamtrace;

TEST(ScanJobConfig, OptionsOverrideOnlyWhatTheyGiveOverTheDemoSensor) {
    bt::ScanJobConfig c;
    c.demo = true;
    bt::ScanSensorOptions o;
    o.width = 64;
    o.vfov_rad = 0.25;
    c.apply(o);
    const bt::ImageSensorConfig demo = bt::demo_sensor();
    EXPECT_EQ(c.sensor.width, 64);
    EXPECT_EQ(c.sensor.height, demo.height);
    EXPECT_EQ(c.sensor.vfov_rad, 0.25);
    EXPECT_EQ(c.sensor.hfov_rad, demo.hfov_rad);
    EXPECT_EQ(c.sensor.position_m.x, demo.position_m.x);
    EXPECT_EQ(c.sensor.orientation.yaw_rad, demo.orientation.yaw_rad);
    EXPECT_FALSE(c.image_width.has_value());
}

TEST(ScanJobConfig, WithoutTheDemoTheDefaultsAreImageSensorConfigs) {
    bt::ScanJobConfig c;
    bt::ScanSensorOptions o;
    o.position_m = bt::Vec3d{1, 2, 3};
    o.orientation_rad = bt::Vec3d{0.1, 0.2, 0.3};
    c.apply(o);
    const bt::ImageSensorConfig d;
    EXPECT_EQ(c.sensor.width, d.width);
    EXPECT_EQ(c.sensor.hfov_rad, d.hfov_rad);
    EXPECT_EQ(c.sensor.position_m.z, 3.0);
    EXPECT_EQ(c.sensor.orientation.roll_rad, 0.1);
    EXPECT_EQ(c.sensor.orientation.pitch_rad, 0.2);
    EXPECT_EQ(c.sensor.orientation.yaw_rad, 0.3);
}

TEST(ScanJobConfig, ForARaysFileTheSizeIsTheRangeImages) {
    bt::ScanJobConfig c;
    c.pattern = bt::parse_pattern_kind("rays");
    bt::ScanSensorOptions o;
    o.width = 8;
    o.height = 4;
    c.apply(o);
    ASSERT_TRUE(c.image_width.has_value());
    EXPECT_EQ(*c.image_width, 8);
    EXPECT_EQ(*c.image_height, 4);
    EXPECT_EQ(c.sensor.width, bt::ImageSensorConfig{}.width);
}

TEST(ScanJobConfig, KdTreeRulesByName) {
    EXPECT_EQ(bt::parse_kdtree_rules("report").rule, bt::KdSplitRule::report);
    EXPECT_EQ(bt::parse_kdtree_rules("report").max_depth,
              bt::KdTreeBuildConfig::report().max_depth);
    EXPECT_EQ(bt::parse_kdtree_rules("sah").rule, bt::KdSplitRule::sah);
    try {
        (void)bt::parse_kdtree_rules("median");
        FAIL() << "no error";
    } catch (const bt::ConfigError& e) {
        EXPECT_STREQ(e.what(), "unknown k-d tree rule set 'median' (expected sah or report)");
    }
}

TEST(Vec3Text, ParsesThreeNumbersAndRefusesTheRest) {
    const bt::Vec3d v = bt::parse_vec3(" 1.5, -2,3e2 ", "--position");
    EXPECT_EQ(v.x, 1.5);
    EXPECT_EQ(v.y, -2.0);
    EXPECT_EQ(v.z, 300.0);
    for (const char* bad : {"1,2", "1,2,3,4", "1,,3", "a,2,3", "1,2,nan", "1,2,3x", ""}) {
        try {
            (void)bt::parse_vec3(bad, "--position");
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const bt::ConfigError& e) {
            EXPECT_EQ(
                std::string(e.what()),
                std::string("--position expects three comma-separated numbers, got '") + bad + "'");
        }
    }
}
