#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/physics/atmosphere.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/physics/range_equation.hpp"

namespace beamtrace {
namespace {

constexpr double kPi = std::numbers::pi;

/// The hits of every sub-ray of `sim` along axis +x against the plane through (range, 0, 0)
/// whose normal is tilted by `incidence_rad` from -x about z.
std::vector<SubRayHit> plane_hits(const PulseSimulator& sim, double range_m, double incidence_rad,
                                  double reflectance) {
    std::vector<Vec3d> dirs(sim.sub_ray_count());
    sim.sub_ray_directions(1, 0, {1, 0, 0}, dirs);
    const Vec3d normal{-std::cos(incidence_rad), std::sin(incidence_rad), 0};
    const Vec3d p0{range_m, 0, 0};
    Material m;
    m.reflectance = reflectance;
    std::vector<SubRayHit> hits;
    for (const auto& d : dirs) {
        const double t = dot(p0, normal) / dot(d, normal);
        hits.push_back(make_sub_ray_hit(m, t, d * t, normal, d));
    }
    return hits;
}

PhysicsConfig vacuum_ray() {
    PhysicsConfig c;
    c.atmosphere.enabled = false;
    c.radiometry.detection_threshold_w = 1e-12;
    return c;
}

TEST(PhysicsRangeEquation, MatchesTheClosedForm) {
    RadiometryConfig r;
    const double area = kPi * 0.05 * 0.05 / 4;
    EXPECT_DOUBLE_EQ(aperture_area_m2(r), area);
    const double p = received_power_w(r, 1000.0, 0.3, 0.8, 40.0, 0.9);
    EXPECT_NEAR(p, 1000.0 * 0.3 * 0.8 * area / (kPi * 1600.0) * 0.8 * 0.9, 1e-15);
    EXPECT_EQ(received_power_w(r, 1000.0, 0.3, 0.8, 0.0, 1.0), 0.0);
}

// Acceptance: a Lambertian plane at range R and incidence theta gives intensity ~ cos(theta)/R^2
// within 1 %, through the whole pulse (waveform, echo fit), for an ideal ray and for a 19-sub-ray
// beam whose footprint spreads over a range of depths on the tilted plane.
TEST(PhysicsRangeEquation, LambertianPlaneIsCosOverRSquared) {
    for (const double divergence : {0.0, 0.5e-3}) {
        PhysicsConfig c = vacuum_ray();
        c.beam.divergence_rad = divergence;
        const PulseSimulator sim(c);
        const auto ref_hits = plane_hits(sim, 10.0, 0.0, 0.5);
        const PulseResponse ref = simulate_pulse(c, 1, 0, ref_hits);
        ASSERT_EQ(ref.returns.size(), 1u);
        EXPECT_NEAR(ref.returns[0].range_m, 10.0, 1e-3);
        for (const double range : {5.0, 20.0, 80.0, 300.0}) {
            for (const double deg : {0.0, 30.0, 60.0, 75.0}) {
                const double th = deg * kPi / 180;
                const PulseResponse r = simulate_pulse(c, 1, 0, plane_hits(sim, range, th, 0.5));
                ASSERT_EQ(r.returns.size(), 1u) << range << " m " << deg << " deg";
                const double expected = std::cos(th) * (10.0 / range) * (10.0 / range);
                EXPECT_NEAR(r.returns[0].power_w / ref.returns[0].power_w, expected,
                            0.01 * expected)
                    << "divergence " << divergence << ", " << range << " m, " << deg << " deg";
                EXPECT_NEAR(r.returns[0].range_m, range, 0.01 + range * std::tan(th) * divergence);
            }
        }
    }
}

TEST(PhysicsRangeEquation, ReflectanceScalesLinearlyAndThresholdDropsWeakReturns) {
    PhysicsConfig c = vacuum_ray();
    const PulseSimulator sim(c);
    const PulseResponse a = simulate_pulse(c, 1, 0, plane_hits(sim, 50, 0, 0.2));
    const PulseResponse b = simulate_pulse(c, 1, 0, plane_hits(sim, 50, 0, 0.6));
    ASSERT_EQ(a.returns.size(), 1u);
    ASSERT_EQ(b.returns.size(), 1u);
    EXPECT_NEAR(b.returns[0].power_w / a.returns[0].power_w, 3.0, 1e-6);
    // The analytic power: P_t a cos A / (pi R^2) eta.
    const double expected =
        received_power_w(c.radiometry, c.radiometry.peak_power_w, 0.2, 1.0, 50.0, 1.0);
    EXPECT_NEAR(a.returns[0].amplitude_w, expected, 1e-6 * expected);
    EXPECT_NEAR(a.returns[0].echo_width_ns, c.waveform.pulse_fwhm_ns, 1e-6);
    // A threshold just above the echo loses it; just below keeps it.
    c.radiometry.detection_threshold_w = expected * 1.01;
    EXPECT_TRUE(simulate_pulse(c, 1, 0, plane_hits(sim, 50, 0, 0.2)).returns.empty());
    c.radiometry.detection_threshold_w = expected * 0.99;
    EXPECT_EQ(simulate_pulse(c, 1, 0, plane_hits(sim, 50, 0, 0.2)).returns.size(), 1u);
}

TEST(PhysicsRangeEquation, LasIntensityScaling) {
    RadiometryConfig r;
    const double fs = intensity_full_scale_w(r);
    EXPECT_NEAR(fs, received_power_w(r, r.peak_power_w, 1.0, 1.0, 10.0, 1.0), 1e-18);
    EXPECT_EQ(las_intensity(r, fs), 65535);
    EXPECT_EQ(las_intensity(r, 10 * fs), 65535);
    EXPECT_EQ(las_intensity(r, 0.25 * fs), 16384);
    EXPECT_EQ(las_intensity(r, 0.0), 0);
    EXPECT_EQ(las_intensity(r, 1e-9 * fs), 1) << "a detected return never reads 0";
    r.intensity_scale = IntensityScale::logarithmic;
    EXPECT_EQ(las_intensity(r, r.detection_threshold_w), 1);
    EXPECT_EQ(las_intensity(r, fs), 65535);
    const double mid = std::sqrt(r.detection_threshold_w * fs);  // halfway in decibels
    EXPECT_NEAR(las_intensity(r, mid), 32768, 1);
    EXPECT_EQ(parse_intensity_scale("logarithmic"), IntensityScale::logarithmic);
    EXPECT_THROW((void)parse_intensity_scale("cubic"), ConfigError);
}

// Unset, R_ref is 10 m for direct users of the library; a number moves the full scale with
// (R_ref)^2; a white Lambertian facing the sensor at R_ref in vacuum reads 65535 through the pulse.
TEST(PhysicsRangeEquation, ReferenceRangeSetsTheFullScale) {
    RadiometryConfig r;
    EXPECT_FALSE(r.intensity_reference_range_m.has_value());
    EXPECT_EQ(intensity_reference_range_m(r), kDefaultIntensityReferenceRange_m);
    EXPECT_EQ(kDefaultIntensityReferenceRange_m, 10.0);
    const double fs10 = intensity_full_scale_w(r);
    r.intensity_reference_range_m = 1500.0;
    EXPECT_NEAR(intensity_full_scale_w(r), fs10 * 1e-2 / 225.0, 1e-12 * fs10);
    r.intensity_reference_range_m = -1.0;
    EXPECT_FALSE(r.validate().empty());
    for (const double range : {10.0, 1500.0}) {
        PhysicsConfig c = vacuum_ray();
        c.radiometry.intensity_reference_range_m = range;
        const PulseSimulator sim(c);
        const PulseResponse white = simulate_pulse(c, 1, 0, plane_hits(sim, range, 0.0, 1.0));
        ASSERT_EQ(white.returns.size(), 1u);
        EXPECT_NEAR(white.returns[0].intensity, 65535, 2) << range;
        const PulseResponse grey = simulate_pulse(c, 1, 0, plane_hits(sim, range, 0.0, 0.25));
        EXPECT_NEAR(grey.returns.at(0).intensity, 0.25 * 65535, 2) << range;
    }
}

TEST(PhysicsAtmosphere, KimModelValues) {
    // Clear air, 23 km, 1064 nm: q = 1.3, alpha = 3.912 / 23 * (1064 / 550)^-1.3 = 0.0721 / km.
    EXPECT_NEAR(extinction_per_m(ExtinctionModel::kim, 23.0, 1064.0), 7.213e-5, 0.01e-5);
    EXPECT_DOUBLE_EQ(extinction_exponent(ExtinctionModel::kim, 60.0), 1.6);
    EXPECT_DOUBLE_EQ(extinction_exponent(ExtinctionModel::kim, 3.0), 0.16 * 3 + 0.34);
    EXPECT_DOUBLE_EQ(extinction_exponent(ExtinctionModel::kim, 0.8), 0.3);
    EXPECT_DOUBLE_EQ(extinction_exponent(ExtinctionModel::kim, 0.2), 0.0);
    EXPECT_DOUBLE_EQ(extinction_exponent(ExtinctionModel::kruse, 1.0), 0.585);
    // Continuous where Kim's pieces meet.
    EXPECT_NEAR(extinction_exponent(ExtinctionModel::kim, 6.0), 1.3, 1e-12);
    EXPECT_NEAR(extinction_exponent(ExtinctionModel::kim, 1.0), 0.5, 1e-12);
    // Fog: no wavelength dependence; at 550 nm the Koschmieder value for any model.
    EXPECT_DOUBLE_EQ(extinction_per_m(ExtinctionModel::kim, 0.2, 1550.0), 3.912 / 0.2 / 1000);
    EXPECT_NEAR(extinction_per_m(ExtinctionModel::kruse, 10.0, 550.0), 3.912e-4, 1e-15);
    // Longer wavelengths see less haze.
    EXPECT_LT(extinction_per_m(ExtinctionModel::kim, 10.0, 1550.0),
              extinction_per_m(ExtinctionModel::kim, 10.0, 905.0));
    AtmosphereConfig a;
    a.extinction_per_m_override = 1e-3;
    EXPECT_EQ(extinction_per_m(a, 1064.0), 1e-3);
    a.enabled = false;
    EXPECT_EQ(extinction_per_m(a, 1064.0), 0.0);
    a.visibility_km = 0;
    EXPECT_EQ(a.validate().size(), 1u);
    EXPECT_THROW((void)parse_extinction_model("mie"), ConfigError);
}

// Acceptance: the received power with extinction alpha is exp(-2 alpha R) times the vacuum one.
TEST(PhysicsAtmosphere, ExtinctionIsTwoWay) {
    PhysicsConfig vac = vacuum_ray();
    PhysicsConfig haze = vac;
    haze.atmosphere.enabled = true;
    haze.atmosphere.visibility_km = 2.0;  // hazy: alpha ~ 0.8 / km at 1064 nm
    const PulseSimulator sim(haze);
    const double alpha = sim.extinction_per_m();
    EXPECT_NEAR(alpha, extinction_per_m(ExtinctionModel::kim, 2.0, 1064.0), 1e-18);
    for (const double range : {10.0, 100.0, 1000.0}) {
        const auto hits = plane_hits(sim, range, 0.3, 0.5);
        const PulseResponse a = simulate_pulse(vac, 1, 0, hits);
        const PulseResponse b = simulate_pulse(haze, 1, 0, hits);
        ASSERT_EQ(a.returns.size(), 1u);
        ASSERT_EQ(b.returns.size(), 1u);
        EXPECT_NEAR(b.returns[0].power_w / a.returns[0].power_w, std::exp(-2 * alpha * range),
                    1e-9);
        EXPECT_NEAR(two_way_transmission(alpha, range), std::exp(-2 * alpha * range), 1e-15);
    }
}

TEST(PhysicsConfig, ValidateCollectsEveryProblemAndTheSimulatorThrows) {
    PhysicsConfig c;
    EXPECT_TRUE(c.validate().empty());
    c.radiometry.peak_power_w = 0;
    c.radiometry.system_efficiency = 2;
    c.atmosphere.visibility_km = -1;
    c.beam.rings = -1;
    c.noise.range_sigma_m = -1;
    c.noise.dropout_probability = 2;
    c.waveform.bin_ns = 10;
    c.max_returns = 0;
    EXPECT_EQ(c.validate().size(), 8u);
    EXPECT_THROW(PulseSimulator{c}, ConfigError);
    EXPECT_EQ(parse_return_mode("strongest"), ReturnMode::strongest);
    EXPECT_THROW((void)parse_return_mode("second"), ConfigError);
}

}  // namespace
}  // namespace beamtrace
