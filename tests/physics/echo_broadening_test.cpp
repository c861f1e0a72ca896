// Echoes of a smooth tilted plane: one return per pulse at every incidence, its width following
// the broadening of a continuous Gaussian footprint (Gardner 1992):
//   sigma_e^2 = sigma_p^2 + (2 sigma_R / c)^2,  sigma_R = tan i W(R) / 2,
// W(R) the footprint's 1/e^2 radius.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "beamtrace/physics/pulse.hpp"

namespace beamtrace {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const double kFwhmPerSigma = 2.0 * std::sqrt(2.0 * std::log(2.0));

PhysicsConfig plane_config(double divergence_rad, int rings, double exit_diameter_m = 0.0) {
    PhysicsConfig c;
    c.beam.divergence_rad = divergence_rad;
    c.beam.rings = rings;
    c.beam.exit_diameter_m = exit_diameter_m;
    c.atmosphere.enabled = false;
    c.radiometry.detection_threshold_w = 1e-12;  // low enough that any weak bump would show
    c.keep_waveform = true;
    return c;
}

/// The sub-ray hits of a beam along +x from the origin on the plane through (range_m, 0, 0)
/// tilted by `incidence` from the beam axis towards the azimuth `tilt_azimuth`.
std::vector<SubRayHit> plane_hits(const PulseSimulator& sim, double range_m, double incidence,
                                  double tilt_azimuth) {
    const std::size_t n = sim.sub_ray_count();
    std::vector<Vec3d> origins(n), dirs(n);
    sim.sub_rays(1, 0, {0, 0, 0}, {1, 0, 0}, origins, dirs);
    const Vec3d normal{std::cos(incidence), std::sin(incidence) * std::cos(tilt_azimuth),
                       std::sin(incidence) * std::sin(tilt_azimuth)};
    const Vec3d p0{range_m, 0, 0};
    std::vector<SubRayHit> hits(n);
    for (std::size_t j = 0; j < n; ++j) {
        hits[j].albedo = 0.4;
        hits[j].cos_incidence = std::abs(dot(normal, dirs[j]));
        hits[j].range_m = dot(p0 - origins[j], normal) / dot(dirs[j], normal);
    }
    return hits;
}

/// Gardner's echo sigma [ns] of the continuous beam on the plane.
double gardner_sigma_ns(const PhysicsConfig& c, double range_m, double incidence) {
    const double sigma_p = c.waveform.pulse_fwhm_ns / kFwhmPerSigma;
    const double sigma_r = std::tan(incidence) * footprint_radius_m(c.beam, range_m) / 2.0;
    const double spread = sigma_r * round_trip_ns_per_m();
    return std::sqrt(sigma_p * sigma_p + spread * spread);
}

/// The RMS width of the whole sampled waveform [ns].
double waveform_sigma_ns(const Waveform& w) {
    double m0 = 0, m1 = 0, m2 = 0;
    for (std::size_t k = 0; k < w.samples_w.size(); ++k) {
        const double t = w.time_ns(k) - w.time_ns(0);
        m0 += w.samples_w[k];
        m1 += w.samples_w[k] * t;
        m2 += w.samples_w[k] * t * t;
    }
    const double mean = m1 / m0;
    return std::sqrt(m2 / m0 - mean * mean);
}

struct Case {
    double range_m;
    double divergence_rad;
    int rings;
    double exit_diameter_m;
};

// Acceptance: 0..85 deg, 50 m and 2000 m, 7 and 19 sub-rays, 0.22 and 0.5 mrad: exactly one
// return, its width within 5 % of Gardner's, the whole waveform's RMS width within 1 %.
TEST(PhysicsEchoBroadening, TiltedPlaneGivesOneBroadenedEcho) {
    std::vector<Case> cases;
    for (const double range : {50.0, 2000.0}) {
        for (const double div : {0.22e-3, 0.5e-3}) {
            for (const int rings : {1, 2}) {
                cases.push_back({range, div, rings, 0.0});
            }
        }
    }
    cases.push_back({50.0, 0.22e-3, 2, 0.02});  // the exit beam dominates the footprint
    cases.push_back({20.0, 0.5e-3, 1, 0.05});
    int checked = 0;
    for (const Case& k : cases) {
        const PhysicsConfig c = plane_config(k.divergence_rad, k.rings, k.exit_diameter_m);
        const PulseSimulator sim(c);
        PulseResponse r;
        for (int deg = 0; deg <= 85; ++deg) {
            for (const double tilt : {0.0, 0.3, 0.5236, 1.1}) {
                const double inc = deg * kDeg;
                sim.simulate(1, 0, plane_hits(sim, k.range_m, inc, tilt), r);
                const std::string where = "R " + std::to_string(k.range_m) + " div " +
                                          std::to_string(k.divergence_rad) + " rings " +
                                          std::to_string(k.rings) + " D0 " +
                                          std::to_string(k.exit_diameter_m) + " incidence " +
                                          std::to_string(deg) + " tilt " + std::to_string(tilt);
                ASSERT_EQ(r.echoes.size(), 1u) << where;
                ASSERT_EQ(r.returns.size(), 1u) << where;
                const double expected = gardner_sigma_ns(c, k.range_m, inc);
                const double width = r.returns[0].echo_width_ns / kFwhmPerSigma;
                EXPECT_NEAR(width / expected, 1.0, 0.05) << where;
                EXPECT_NEAR(waveform_sigma_ns(r.waveform) / expected, 1.0, 0.01) << where;
                // The energy is kept: the equivalent power is the sub-rays' sum.
                double total = 0;
                for (const double p : r.sub_ray_power_w) {
                    total += p;
                }
                EXPECT_NEAR(r.returns[0].power_w / total, 1.0, 1e-3) << where;
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 10 * 86 * 4);
}

// The case: 0.22 mrad, 19 sub-rays, 4 ns, 1500-2000 m at 83-85 deg used to give 2-5
// echoes; the stretch of a single sub-ray's echo is what merges them.
TEST(PhysicsEchoBroadening, SteepIncidenceAtLongRangeIsOneEcho) {
    const PulseSimulator sim(plane_config(0.22e-3, 2));
    PulseResponse r;
    for (const double range : {1500.0, 1750.0, 2000.0}) {
        for (const double deg : {83.0, 84.0, 85.0}) {
            for (int a = 0; a < 12; ++a) {
                sim.simulate(1, 0, plane_hits(sim, range, deg * kDeg, a * std::numbers::pi / 36),
                             r);
                EXPECT_EQ(r.echoes.size(), 1u) << range << " m, " << deg << " deg, tilt " << a;
            }
        }
    }
}

// A sub-ray's echo is stretched by its footprint cell with its energy kept.
TEST(PhysicsEchoBroadening, SubRayEchoSigmaFollowsItsCell) {
    const PhysicsConfig c = plane_config(0.5e-3, 2);
    const PulseSimulator sim(c);
    const double sigma_p = c.waveform.pulse_fwhm_ns / kFwhmPerSigma;
    SubRayHit h;
    h.range_m = 1000.0;
    h.cos_incidence = 1.0;
    EXPECT_DOUBLE_EQ(sim.echo_sigma_ns(h), sigma_p);  // normal incidence: no stretch
    h.cos_incidence = std::cos(60 * kDeg);
    const double cell = std::sqrt(cell_variance(sim.pattern()));
    const double spread = std::tan(60 * kDeg) * cell * 0.25 * round_trip_ns_per_m();
    EXPECT_NEAR(sim.echo_sigma_ns(h), std::hypot(sigma_p, spread), 1e-9);
    // Grazing: tan i is capped at 89.5 deg.
    h.cos_incidence = 0.0;
    const double capped = std::tan(89.5 * kDeg) * cell * 0.25 * round_trip_ns_per_m();
    EXPECT_NEAR(sim.echo_sigma_ns(h), std::hypot(sigma_p, capped), 1e-6 * capped);
    // No divergence, no exit diameter: an ideal ray has the pulse's width.
    const PulseSimulator ideal(plane_config(0.0, 2));
    EXPECT_EQ(ideal.echo_sigma_ns(h), sigma_p);
}

// Without an exit diameter every sub-ray starts bit for bit at the sensor's origin (the
// default changes nothing); with one, they start in the exit pupil around it.
TEST(PhysicsEchoBroadening, SubRaysStartAtTheOriginWithoutExitDiameter) {
    PhysicsConfig c = plane_config(0.5e-3, 2);
    const Vec3d origin{-0.0, 1e-300, 12345.678};
    const Vec3d axis = normalize(Vec3d{0.2, 0.1, -1});
    std::vector<Vec3d> origins(19), dirs(19), plain(19);
    const PulseSimulator sim(c);
    sim.sub_rays(7, 3, origin, axis, origins, dirs);
    sim.sub_ray_directions(7, 3, axis, plain);
    for (std::size_t j = 0; j < 19; ++j) {
        EXPECT_EQ(std::memcmp(&origins[j], &origin, sizeof origin), 0) << j;
        EXPECT_EQ(dirs[j], plain[j]);
    }
    c.beam.exit_diameter_m = 0.1;
    const PulseSimulator wide(c);
    wide.sub_rays(7, 3, origin, axis, origins, dirs);
    double widest = 0;
    for (std::size_t j = 0; j < 19; ++j) {
        EXPECT_NEAR(dot(origins[j] - origin, axis), 0.0, 1e-9);  // in the exit pupil's plane
        widest = std::max(widest, length(origins[j] - origin));
    }
    EXPECT_NEAR(widest, 0.05 * wide.pattern()[18].radius, 1e-9);
}

}  // namespace
}  // namespace beamtrace
