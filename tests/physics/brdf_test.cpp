// The BRDFs of physics/material.hpp: the normalised Phong lobe conserves energy (its
// directional albedo, integrated over the viewing hemisphere, is the albedo at normal incidence
// and never more), calm water flashes at nadir, and a Lambertian surface is the same in both.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>

#include "beamtrace/core/error.hpp"
#include "beamtrace/physics/material.hpp"
#include "beamtrace/physics/material_library.hpp"
#include "beamtrace/physics/pulse.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

/// The directional albedo per unit albedo, rho(i) / a = integral over the viewing hemisphere of
/// f_r / a cos e, with f_r / a = L(i, e, g) / (pi cos i) of `brdf`, for light at incidence
/// `incidence_rad`. Midpoint rule in a frame about the mirror direction r (theta' = pi t^2
/// crowds the samples into the lobe; the integrand is symmetric in phi').
double directional_albedo(Brdf brdf, double incidence_rad, double s, double n) {
    const Vec3d to_light{std::sin(incidence_rad), 0, std::cos(incidence_rad)};
    const Vec3d mirror{-to_light.x, 0, to_light.z};
    const Vec3d e1{to_light.z, 0, to_light.x}, e2{0, 1, 0};
    constexpr int kT = 300, kPhi = 120;
    double sum = 0.0;
    for (int it = 0; it < kT; ++it) {
        const double t = (it + 0.5) / kT;
        const double theta = kPi * t * t, dtheta = 2 * kPi * t / kT;
        for (int ip = 0; ip < kPhi; ++ip) {
            const double phi = kPi * (ip + 0.5) / kPhi;
            const Vec3d w = mirror * std::cos(theta) +
                            (e1 * std::cos(phi) + e2 * std::sin(phi)) * std::sin(theta);
            if (!(w.z > 0)) {
                continue;
            }
            const double l = reflectance(brdf, to_light.z, w.z, dot(w, to_light), s, n);
            sum += l / (kPi * to_light.z) * w.z * std::sin(theta) * dtheta;
        }
    }
    return sum * 2.0 * kPi / kPhi;  // both halves of phi'
}

// Acceptance: for incidences 0..89 degrees and several (s, n), the normalised Phong BRDF never
// reflects more than its albedo, and exactly its albedo (s a + (1 - s) a) at normal incidence.
TEST(PhysicsBrdf, NormalizedPhongDirectionalAlbedoNeverExceedsTheAlbedo) {
    for (const auto& [s, n] : {std::pair{0.0, 10.0}, std::pair{0.5, 10.0}, std::pair{1.0, 1.0},
                               std::pair{0.3, 50.0}, std::pair{0.9, 500.0}}) {
        EXPECT_NEAR(directional_albedo(Brdf::normalized_phong, 0.0, s, n), 1.0, 1e-3)
            << "s " << s << " n " << n;
        double previous = 2.0;
        for (int deg = 0; deg < 90; ++deg) {
            const double rho = directional_albedo(Brdf::normalized_phong, deg * kPi / 180, s, n);
            EXPECT_LE(rho, 1.0 + 2e-3) << "s " << s << " n " << n << " at " << deg << " deg";
            EXPECT_GT(rho, 0.0);
            EXPECT_LE(rho, previous + 2e-3) << "falls with incidence";
            previous = rho;
        }
    }
}

// The same integral catches the seed's phenomenological lobe, which is not energy-conserving:
// at grazing incidence with a small exponent it reflects half as much again as its albedo.
TEST(PhysicsBrdf, PhenomenologicalLobeIsNotEnergyConserving) {
    EXPECT_GT(directional_albedo(Brdf::phenomenological, 80 * kPi / 180, 1.0, 1.0), 1.5);
    // At normal incidence its lobe carries only about 2 s / (n + 2) of the energy.
    EXPECT_NEAR(directional_albedo(Brdf::phenomenological, 0.0, 1.0, 50.0), 2.0 / 52.0, 2e-3);
}

TEST(PhysicsBrdf, LambertianIsTheSameInBothForms) {
    for (double deg = 0; deg < 90; deg += 7.5) {
        const double c = std::cos(deg * kPi / 180);
        EXPECT_EQ(monostatic_reflectance(Brdf::normalized_phong, c, 0.0, 10.0), c);
        EXPECT_EQ(monostatic_reflectance(Brdf::phenomenological, c, 0.0, 10.0), c);
        EXPECT_EQ(normalized_phong_reflectance(c, 0.3, 0.1, 0.0, 10.0), c);
    }
    EXPECT_EQ(monostatic_reflectance(Brdf::normalized_phong, -0.2, 0.5, 10.0), 0.0);
    EXPECT_DOUBLE_EQ(normalized_phong_brdf(0.7, 0.0, 10.0), 1.0 / kPi);
}

TEST(PhysicsBrdf, MonostaticNormalizedPhongClosedForm) {
    for (const double s : {0.2, 0.9}) {
        for (const double n : {4.0, 40.0}) {
            for (double deg = 0; deg < 90; deg += 5) {
                const double i = deg * kPi / 180;
                const double c2 = std::max(0.0, std::cos(2 * i));
                const double want =
                    (1 - s) * std::cos(i) + s * (n + 2) / 2 * std::pow(c2, n) * std::cos(i);
                EXPECT_NEAR(monostatic_reflectance(Brdf::normalized_phong, std::cos(i), s, n), want,
                            1e-12 * (1 + want));
            }
        }
    }
    EXPECT_EQ(parse_brdf("normalized_phong"), Brdf::normalized_phong);
    EXPECT_EQ(to_string(Brdf::phenomenological), "phenomenological");
    EXPECT_THROW((void)parse_brdf("cook_torrance"), ConfigError);
}

// Acceptance: library water (albedo 0.02, s 0.9, n 500) gives a strong specular flash at nadir
// through the pulse's power (far above a 2 % Lambertian), and is dark off the mirror angle.
TEST(PhysicsBrdf, LibraryWaterFlashesAtNadir) {
    const Material water = library_material("water", 1064.0).value();
    PhysicsConfig c;
    c.atmosphere.enabled = false;
    const PulseSimulator sim(c);
    const auto power = [&](const PulseSimulator& p, const Material& m, double incidence_deg) {
        SubRayHit h;
        h.range_m = 100.0;
        h.cos_incidence = std::cos(incidence_deg * kPi / 180);
        h.albedo = m.reflectance;
        h.specular_weight = m.specular_weight;
        h.specular_exponent = m.specular_exponent;
        return p.sub_ray_power_w(h, 1.0);
    };
    Material lambert;
    lambert.reflectance = 0.02;
    const double flash = power(sim, water, 0.0), matte = power(sim, lambert, 0.0);
    EXPECT_GT(flash, 50 * matte);
    EXPECT_NEAR(flash / matte, 0.1 + 0.9 * 251, 1e-9);
    EXPECT_LT(power(sim, water, 20.0), 0.2 * power(sim, lambert, 20.0)) << "dark off nadir";
    // The seed's phenomenological lobe reads water like a 2 % Lambertian at nadir.
    c.brdf = Brdf::phenomenological;
    const PulseSimulator seed_sim(c);
    EXPECT_NEAR(power(seed_sim, water, 0.0) / power(seed_sim, lambert, 0.0), 1.0, 1e-12);
}

}  // namespace
}  // namespace beamtrace
