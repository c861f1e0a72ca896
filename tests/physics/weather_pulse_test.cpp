// The weather inside the pulse simulation: extinction of the hard target's echo, the maximum
// detection range in fog, particle echoes per pulse, and the medium's points marked as such.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/physics/weather.hpp"

namespace beamtrace {
namespace {

/// An ideal ray (one sub-ray) meeting a white-ish Lambertian wall face-on at `range_m`.
std::vector<SubRayHit> wall(double range_m, double albedo = 0.3) {
    SubRayHit h;
    h.range_m = range_m;
    h.cos_incidence = 1.0;
    h.albedo = albedo;
    return {h};
}

PhysicsConfig fog_config(double mor_m, std::optional<double> backscatter = {}) {
    PhysicsConfig c;
    c.atmosphere.enabled = false;
    c.weather.emplace();
    c.weather->fog = FogConfig{mor_m, {}, backscatter};
    return c;
}

TEST(WeatherPulse, HardEchoFollowsTwoWayExtinction) {
    PhysicsConfig clear;
    clear.atmosphere.enabled = false;
    const double r = 30.0;
    const PulseResponse ref = simulate_pulse(clear, 1, 0, wall(r));
    ASSERT_EQ(ref.returns.size(), 1u);
    for (const double mor : {100.0, 150.0, 400.0}) {
        const double alpha = std::log(20.0) / mor;
        // Without the fog's backscatter the echo is the clear one times exp(-2 alpha R) (within
        // 1e-6: the weather's lone pulse has its energy in closed form, within 6e-7 of the
        // clear pulse's sampled sum; docs/weather.md)...
        const PulseResponse dim = simulate_pulse(fog_config(mor, 0.0), 1, 0, wall(r));
        ASSERT_EQ(dim.returns.size(), 1u) << mor;
        EXPECT_NEAR(dim.returns[0].power_w / ref.returns[0].power_w, std::exp(-2 * alpha * r),
                    1e-6 * std::exp(-2 * alpha * r))
            << mor;
        // ... and with it, within 1 % (the fog's own echo at 30 m is far weaker).
        const PulseResponse foggy = simulate_pulse(fog_config(mor), 1, 0, wall(r));
        ASSERT_FALSE(foggy.returns.empty()) << mor;
        const PulseReturn& hard = foggy.returns.back();
        EXPECT_EQ(hard.weather, WeatherEffect::none);
        EXPECT_NEAR(hard.power_w / ref.returns[0].power_w, std::exp(-2 * alpha * r),
                    0.01 * std::exp(-2 * alpha * r))
            << mor;
    }
}

/// The largest range (to 1 cm) at which `detected(range)` holds, below `hi`.
template <typename F>
double last_detected_m(F detected, double lo, double hi) {
    while (hi - lo > 0.01) {
        const double mid = (lo + hi) / 2.0;
        (detected(mid) ? lo : hi) = mid;
    }
    return lo;
}

TEST(WeatherPulse, MaximumRangeInFogSolvesTheRangeEquation) {
    for (const double mor : {30.0, 50.0, 100.0, 200.0}) {
        const PhysicsConfig c = fog_config(mor);
        const PulseSimulator sim(c);
        const double rho = 0.3;
        const auto simulated = [&](double r) {
            PulseResponse out;
            sim.simulate(1, 0, wall(r, rho), out);
            for (const PulseReturn& ret : out.returns) {
                if (ret.weather == WeatherEffect::none && std::abs(ret.range_m - r) < 0.2) {
                    return true;
                }
            }
            return false;
        };
        // P_t rho A_r eta exp(-2 alpha R) / (pi R^2) = threshold, solved by the library.
        const double want = max_detection_range_in_fog_m(c.radiometry, c.atmosphere, rho, mor);
        const double got = last_detected_m(simulated, 3.0, 2000.0);
        EXPECT_NEAR(got, want, 0.02 * want) << "MOR " << mor;
    }
}

/// P_r of a Lambertian target of albedo `rho` facing the sensor at `range_m` through
/// exp(-2 alpha R), written out (not range_equation.hpp's).
double lambertian_power_w(const RadiometryConfig& q, double rho, double alpha, double range_m) {
    return q.peak_power_w * rho * std::numbers::pi * q.aperture_diameter_m * q.aperture_diameter_m /
           4.0 * q.system_efficiency * std::exp(-2 * alpha * range_m) /
           (std::numbers::pi * range_m * range_m);
}

TEST(WeatherPulse, MaximumRangeSolverMeetsTheThresholdExactly) {
    RadiometryConfig q;
    q.wavelength_nm = 905.0;
    q.peak_power_w = 30.0;
    q.detection_threshold_w = 2e-8;
    AtmosphereConfig air;  // 23 km visibility: its extinction adds to the fog's
    for (const double rho : {0.05, 0.1, 0.5, 1.0}) {
        for (const double mor : {5.0, 20.0, 50.0, 200.0, 1000.0, 2000.0, 1e5}) {
            const double r = max_detection_range_in_fog_m(q, air, rho, mor);
            const double alpha = std::log(20.0) / mor + extinction_per_m(air, q.wavelength_nm);
            const double p = lambertian_power_w(q, rho, alpha, r);
            EXPECT_NEAR(p / q.detection_threshold_w, 1.0, 1e-9) << rho << " " << mor;
            // Closer is detected, farther not (the root is the one the curve crosses).
            EXPECT_GT(lambertian_power_w(q, rho, alpha, r * (1 - 1e-6)), q.detection_threshold_w);
            EXPECT_LT(lambertian_power_w(q, rho, alpha, r * (1 + 1e-6)), q.detection_threshold_w);
        }
    }
    // Without extinction the root is sqrt(K).
    AtmosphereConfig vacuum;
    vacuum.enabled = false;
    const double k = q.peak_power_w * 0.5 * q.aperture_diameter_m * q.aperture_diameter_m / 4.0 *
                     q.system_efficiency / q.detection_threshold_w;
    EXPECT_NEAR(max_detection_range_in_fog_m(q, vacuum, 0.5, 1e300), std::sqrt(k),
                1e-9 * std::sqrt(k));
    EXPECT_THROW((void)max_detection_range_in_fog_m(q, air, 0.0, 50.0), ConfigError);
    EXPECT_THROW((void)max_detection_range_in_fog_m(q, air, 0.5, -1.0), ConfigError);
}

TEST(WeatherPulse, ParticleEchoesPerPulseMatchTheExpectedCount) {
    PhysicsConfig c;
    c.atmosphere.enabled = false;
    // About 0.08 echoes per pulse: few pulses hold two particles closer than the waveform
    // resolves (most lie 1 to 2 m away, where the beam is narrow), which would make one echo.
    c.radiometry.peak_power_w = 1.0;
    c.max_returns = 15;
    c.beam.divergence_rad = 3e-3;
    c.beam.rings = 0;
    c.beam.exit_diameter_m = 0.02;
    c.weather.emplace();
    c.weather->precipitation = PrecipitationConfig{PrecipitationKind::rain, 25.0, {}, 1.0};
    const PulseSimulator sim(c);
    // The expected count: particles whose echo alone reaches the threshold, up to the last range
    // any can (the sky: no hard target).
    const auto dsd = drop_size_distribution(PrecipitationKind::rain, 25.0);
    ParticleBeam b;
    b.exit_radius_m = 0.01;
    b.half_angle_rad = 1.5e-3;
    b.emitted_power_w = c.radiometry.peak_power_w;
    b.receiver_gain_m2 = c.radiometry.system_efficiency * aperture_area_m2(c.radiometry);
    b.extinction_per_m = extinction_per_m(dsd);
    b.floor_w = c.radiometry.detection_threshold_w;
    b.start_m = 0.5;
    b.overlap = {0.5, 2.0};
    b.max_range_m = 400.0;
    const ParticleSampler reference(dsd, 0.02, b, {}, 1 << 16);
    const double expected = reference.expected_count(400.0);
    ASSERT_GT(expected, 0.05);
    ASSERT_LT(expected, 0.2);

    const int pulses = 100000;
    std::size_t medium = 0, drawn = 0;
    PulseResponse out;
    const std::vector<SubRayHit> sky(1);
    for (int i = 0; i < pulses; ++i) {
        sim.simulate(9, static_cast<std::uint64_t>(i), sky, out);
        drawn += out.medium.particles.size();
        for (const PulseReturn& r : out.returns) {
            EXPECT_EQ(r.weather, WeatherEffect::rain);
            ++medium;
        }
    }
    const double per_pulse = static_cast<double>(medium) / pulses;
    EXPECT_NEAR(per_pulse, expected, 0.05 * expected);
    // The particles drawn, before the waveform: within 2 % (about 3 standard deviations).
    EXPECT_NEAR(static_cast<double>(drawn) / pulses, expected, 0.02 * expected);
}

TEST(WeatherPulse, ParticlesShadowTheTargetAndMarkTheirEchoes) {
    PhysicsConfig c;
    c.atmosphere.enabled = false;
    c.radiometry.peak_power_w = 10.0;
    c.beam.divergence_rad = 3e-3;
    c.beam.rings = 0;
    c.weather.emplace();
    c.weather->precipitation = PrecipitationConfig{PrecipitationKind::snow, 10.0, {}, 0.25};
    const PulseSimulator sim(c);
    PhysicsConfig clear = c;
    clear.weather.reset();
    const PulseSimulator dry(clear);
    PulseResponse out, ref;
    dry.simulate(1, 0, wall(40.0), ref);
    const double alpha = extinction_per_m(drop_size_distribution(PrecipitationKind::snow, 10.0));
    std::size_t shadowed = 0, snow_points = 0, compared = 0;
    for (std::uint64_t i = 0; i < 5000; ++i) {
        sim.simulate(2, i, wall(40.0), out);
        double blocked = 1.0;
        bool near_target = false;  // a particle whose echo adds to the target's
        for (const Particle& p : out.medium.particles) {
            blocked *= 1.0 - p.blocked_fraction;
            near_target = near_target || p.range_m > 38.0;
        }
        shadowed += blocked < 1.0 ? 1 : 0;
        for (const PulseReturn& r : out.returns) {
            if (r.weather == WeatherEffect::snow) {
                ++snow_points;
                EXPECT_LT(r.range_m, 40.0);
            } else if (std::abs(r.range_m - 40.0) < 0.3 && !near_target) {
                // The target's echo: extinguished and shadowed by the particles in front.
                EXPECT_NEAR(r.power_w,
                            ref.returns[0].power_w * std::exp(-2 * alpha * 40.0) * blocked,
                            1e-4 * r.power_w);
                compared += blocked < 1.0 ? 1 : 0;
            }
        }
    }
    EXPECT_GT(shadowed, 100u);
    EXPECT_GT(compared, 100u);  // shadowed targets checked
    EXPECT_GT(snow_points, 100u);
}

}  // namespace
}  // namespace beamtrace
