// Wet and snow-covered materials against the film model's sums and the library's snow.
#include <gtest/gtest.h>

#include <cmath>

#include "beamtrace/physics/material_library.hpp"
#include "beamtrace/physics/wetness.hpp"

namespace beamtrace {
namespace {

TEST(Wetness, ConstantsFollowFromTheRefractiveIndexOfWater) {
    const double n = 1.33;
    EXPECT_NEAR(kWaterNormalReflectance, std::pow((n - 1) / (n + 1), 2), 1e-6);
    EXPECT_NEAR(kWaterInternalDiffuseReflectance, 1.0 - (1.0 - 0.066) / (n * n), 1e-5);
}

TEST(Wetness, WetAlbedoIsTheSumOfTheFilmsBounces) {
    for (const double a : {0.0, 0.05, 0.3, 0.5, 0.9, 1.0}) {
        // Light in: 1 - R0; each bounce off the surface (a) lets 1 - r_i out, returns r_i.
        double out = 0.0, inside = (1.0 - kWaterNormalReflectance) * a;
        for (int bounce = 0; bounce < 200; ++bounce) {
            out += inside * (1.0 - kWaterInternalDiffuseReflectance);
            inside *= kWaterInternalDiffuseReflectance * a;
        }
        EXPECT_NEAR(wet_albedo(a), out, 1e-12) << a;
        EXPECT_LE(wet_albedo(a), a) << a;  // never brighter
    }
    EXPECT_NEAR(wet_albedo(0.5), 0.339, 0.001);
}

TEST(Wetness, WetnessBlendsDryAndWet) {
    Material dry;
    dry.reflectance = 0.4;
    dry.specular_weight = 0.1;
    dry.specular_exponent = 20.0;
    const Material same = wet_material(dry, 0.0);
    EXPECT_EQ(same.reflectance, dry.reflectance);
    EXPECT_EQ(same.specular_weight, dry.specular_weight);
    const Material half = wet_material(dry, 0.5);
    EXPECT_NEAR(half.reflectance, 0.5 * 0.4 + 0.5 * wet_albedo(0.4), 1e-15);
    EXPECT_NEAR(half.specular_weight, 0.1 + 0.5 * kWaterNormalReflectance, 1e-15);
    EXPECT_EQ(half.specular_exponent, kWaterSpecularExponent);
    const Material soaked = wet_material(dry, 1.0);
    EXPECT_NEAR(soaked.reflectance, wet_albedo(0.4), 1e-15);
    EXPECT_TRUE(soaked.validate().empty());
}

TEST(Wetness, SnowCoverTakesTheLibrarysSnowAtTheWavelength) {
    Material asphalt = library_material("asphalt", 905.0).value();
    const Material snow905 = library_material("snow", 905.0).value();
    const Material snow1550 = library_material("snow", 1550.0).value();
    const Material full = snow_covered_material(asphalt, 1.0, 905.0);
    EXPECT_NEAR(full.reflectance, snow905.reflectance, 1e-15);
    const Material quarter = snow_covered_material(asphalt, 0.25, 1550.0);
    EXPECT_NEAR(quarter.reflectance, 0.75 * asphalt.reflectance + 0.25 * snow1550.reflectance,
                1e-15);
    EXPECT_EQ(snow_covered_material(asphalt, 0.0, 905.0).reflectance, asphalt.reflectance);
    // Snow is bright at 905 nm and nearly black at 1550 nm (the library's note).
    EXPECT_GT(snow905.reflectance, 0.5);
    EXPECT_LT(snow1550.reflectance, 0.2);
}

}  // namespace
}  // namespace beamtrace
