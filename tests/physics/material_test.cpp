#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "beamtrace/physics/material.hpp"
#include "beamtrace/physics/material_library.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(PhysicsMaterial, LambertianIsCosIncidence) {
    for (double deg = 0; deg < 90; deg += 7.5) {
        const double c = std::cos(deg * kPi / 180);
        EXPECT_DOUBLE_EQ(monostatic_reflectance(c, 0.0, 10.0), c);
        EXPECT_DOUBLE_EQ(phenomenological_reflectance(c, 0.3, 0.1, 0.0, 10.0), c);
    }
    EXPECT_EQ(monostatic_reflectance(-0.2, 0.5, 10.0), 0.0);  // self-shadowed
    EXPECT_EQ(monostatic_reflectance(0.0, 0.0, 10.0), 0.0);
}

TEST(PhysicsMaterial, MonostaticSpecularIsCosTwoI) {
    const double s = 0.4, n = 7.0;
    for (double deg = 0; deg < 90; deg += 5) {
        const double i = deg * kPi / 180;
        const double c2 = std::cos(2 * i);
        const double expected = s * (c2 > 0 ? std::pow(c2, n) : 0.0) + (1 - s) * std::cos(i);
        EXPECT_NEAR(monostatic_reflectance(std::cos(i), s, n), expected, 1e-12) << deg;
    }
    EXPECT_NEAR(monostatic_reflectance(1.0, 1.0, 50.0), 1.0, 1e-12);
}

TEST(PhysicsMaterial, SpecularPeaksAtTheMirrorDirection) {
    Material m;
    m.specular_weight = 1.0;
    m.specular_exponent = 30.0;
    const Vec3d n{0, 0, 1};
    const double inc = 35.0 * kPi / 180;
    const Vec3d to_light{std::sin(inc), 0, std::cos(inc)};
    const Vec3d mirror = n * (2 * dot(n, to_light)) - to_light;
    double best = -1;
    Vec3d best_v;
    for (int a = 0; a < 180; ++a) {      // elevation from the normal, 0.5 degree steps
        for (int b = 0; b < 720; ++b) {  // azimuth
            const double th = a * 0.5 * kPi / 180, ph = b * 0.5 * kPi / 180;
            const Vec3d v{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)};
            const double l = phenomenological_reflectance(m, n, to_light, v);
            if (l > best) {
                best = l;
                best_v = v;
            }
        }
    }
    EXPECT_NEAR(best, 1.0, 1e-3);
    EXPECT_LT(std::acos(std::min(1.0, dot(best_v, mirror))), 0.6 * kPi / 180);
    EXPECT_NEAR(phenomenological_reflectance(m, n, to_light, mirror), 1.0, 1e-12);
    // Off the mirror direction the lobe falls off as cos(angle)^n.
    const double off = 10.0 * kPi / 180;
    const Vec3d v_off{-std::sin(inc + off), 0, std::cos(inc + off)};
    EXPECT_NEAR(phenomenological_reflectance(m, n, to_light, v_off), std::pow(std::cos(off), 30.0),
                1e-12);
}

TEST(PhysicsMaterial, ValidateListsEveryProblem) {
    Material m;
    EXPECT_TRUE(m.validate().empty());
    m.reflectance = 1.5;
    m.specular_weight = -0.1;
    m.specular_exponent = 0;
    m.pattern.kind = AlbedoPatternKind::stripes;
    m.pattern.count = 1;
    m.pattern.size_m = 0;
    m.pattern.alternate_reflectance = 2;
    m.color = {1, -0.5, 0};
    EXPECT_EQ(m.validate().size(), 7u);
    m.pattern.kind = AlbedoPatternKind::uniform;  // an unused pattern is not checked
    EXPECT_EQ(m.validate().size(), 4u);
}

TEST(PhysicsMaterial, LibraryIsPlausible) {
    std::set<std::string_view> names;
    for (const auto& nm : material_library()) {
        EXPECT_TRUE(names.insert(nm.name).second) << nm.name;
        for (const double w : {905.0, 1064.0, 1550.0, 1300.0}) {
            const auto m = library_material(nm.name, w);
            ASSERT_TRUE(m.has_value());
            EXPECT_TRUE(m->validate().empty()) << nm.name;
        }
    }
    for (const char* n : {"asphalt", "concrete", "grass", "vegetation", "metal", "snow"}) {
        EXPECT_TRUE(names.count(n)) << n;
    }
    const Material snow = library_material("snow", 1550.0).value();
    EXPECT_LT(snow.reflectance, 0.1);  // ice absorbs at 1550 nm
    const auto& grass = material_library()[2];
    EXPECT_EQ(grass.name, "grass");
    EXPECT_DOUBLE_EQ(reflectance_at(grass, (905.0 + 1064.0) / 2),
                     (grass.reflectance_905nm + grass.reflectance_1064nm) / 2);
    EXPECT_DOUBLE_EQ(reflectance_at(grass, 2000.0), grass.reflectance_1550nm);
    EXPECT_FALSE(library_material("unobtainium", 1064.0).has_value());
    EXPECT_NE(material_library_names().find("asphalt"), std::string::npos);
}

}  // namespace
}  // namespace beamtrace
