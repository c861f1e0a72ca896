// Beam divergence as data sheets define it (docs/physics.md, "Beam divergence"): the full angle
// theta at the 1/e^2 points of a Gaussian beam, I(alpha) = exp(-8 alpha^2 / theta^2). The
// sub-rays' energies and angles of HELIOS++'s ALS50-II beam (0.22 mrad) follow from that
// definition in closed form, written here in angle units.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "beamtrace/physics/beam_divergence.hpp"

namespace beamtrace {
namespace {

constexpr double kTheta = 0.22e-3;  // full angle at 1/e^2 [rad]

/// Share of the beam's energy between the angles a and b [rad]: the integral of
/// I(alpha) 2 pi alpha d alpha, normalised: exp(-8 a^2 / theta^2) - exp(-8 b^2 / theta^2).
double energy(double a, double b) {
    const auto tail = [](double x) {
        return std::isinf(x) ? 0.0 : std::exp(-8.0 * x * x / (kTheta * kTheta));
    };
    return tail(a) - tail(b);
}

/// The energy-weighted mean angle between a and b: int alpha^2 I / int alpha I, in closed form
/// (int x^2 e^(-k x^2) = -x e^(-k x^2) / 2k + sqrt(pi) erf(sqrt(k) x) / (4 k^1.5)).
double mean_angle(double a, double b) {
    const double k = 8.0 / (kTheta * kTheta);
    const auto m2 = [&](double x) {
        const double t = std::isinf(x) ? 0.0 : x * std::exp(-k * x * x) / (2 * k);
        return -t +
               std::sqrt(std::numbers::pi) * std::erf(std::sqrt(k) * x) / (4 * std::pow(k, 1.5));
    };
    const double m1 = energy(a, b) / (2 * k);  // int x e^(-k x^2) over [a, b]
    return (m2(b) - m2(a)) / m1;
}

TEST(BeamDataSheet, RingsFollowFromTheOneOverESquaredFullAngle) {
    BeamConfig c;
    c.divergence_rad = kTheta;
    c.rings = 2;
    const auto p = beam_pattern(c);
    ASSERT_EQ(p.size(), 19u);
    // The 1/e^2 point is the angle theta / 2 = 0.11 mrad: d = 1 / rings of it per ring.
    const double w = kTheta / 2, inf = std::numeric_limits<double>::infinity();
    const double edges[] = {0.0, 0.25 * w, 0.75 * w, inf};
    const int counts[] = {1, 6, 12};
    std::size_t j = 0;
    for (int ring = 0; ring < 3; ++ring) {
        const double e = energy(edges[ring], edges[ring + 1]);
        const double sector = 2 * std::numbers::pi / counts[ring];
        const double angle = ring == 0 ? 0.0
                                       : mean_angle(edges[ring], edges[ring + 1]) *
                                             std::sin(sector / 2) / (sector / 2);
        for (int s = 0; s < counts[ring]; ++s, ++j) {
            EXPECT_NEAR(p[j].weight, e / counts[ring], 1e-12) << "ring " << ring;
            EXPECT_NEAR(p[j].off_axis_rad, angle, 1e-15) << "ring " << ring;
        }
    }
    // The figures docs/physics.md quotes: 11.75 / 55.78 / 32.47 % of the energy at 0 / 0.0527 /
    // 0.1096 mrad.
    EXPECT_NEAR(p[0].weight, 0.1175, 1e-4);
    EXPECT_NEAR(6 * p[1].weight, 0.5578, 1e-4);
    EXPECT_NEAR(12 * p[7].weight, 0.3247, 1e-4);
    EXPECT_NEAR(p[1].off_axis_rad * 1e3, 0.0527, 1e-4);
    EXPECT_NEAR(p[7].off_axis_rad * 1e3, 0.1096, 1e-4);
    // 1 - e^-2 = 86.5 % of the energy lies within theta / 2: what "at 1/e^2" means.
    EXPECT_NEAR(energy(0.0, w), 1 - std::exp(-2.0), 1e-15);
}

}  // namespace
}  // namespace beamtrace
