#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "beamtrace/physics/pulse.hpp"

namespace beamtrace {
namespace {

/// echo_sigmas (lanes) against echo_sigma_ns (one sample at a time), bit for bit, on samples
/// of every kind: grazing, clamped, missed, NaN, and cells without spread.
void expect_sigmas_match(double exit_diameter_m) {
    PhysicsConfig c;
    c.beam.divergence_rad = 0.5e-3;
    c.beam.rings = 2;
    c.beam.exit_diameter_m = exit_diameter_m;
    const PulseSimulator sim(c);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    std::vector<BeamSample> samples;
    std::uint64_t s = 7;
    const auto next = [&s] {
        s = s * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(s >> 11) * 0x1p-53;
    };
    const double odd_cos[] = {1.0, 1.5, 0.0, -0.2, 0.008, 0.0087, nan};
    const double odd_range[] = {0.0, -3.0, inf, nan, 1e-300};
    for (int i = 0; i < 203; ++i) {  // not a multiple of 4: the tail too
        SubRayHit h;
        h.range_m = i % 9 == 0 ? odd_range[(i / 9) % 5] : 50.0 + 3000.0 * next();
        h.cos_incidence = i % 7 == 0 ? odd_cos[(i / 7) % 7] : next();
        BeamSample b = sim.cell_sample(h, static_cast<std::size_t>(i) % sim.sub_ray_count());
        if (i % 11 == 0) {
            b.cell_sigma = i % 22 == 0 ? 0.0 : 0.05;  // a cell without spread, a probe's
        }
        samples.push_back(b);
    }
    std::vector<double> got;
    sim.echo_sigmas(samples, got);
    ASSERT_EQ(got.size(), samples.size());
    const double beam_cell_sigma = sim.cell_sample(SubRayHit{}, 0).cell_sigma;
    SubRayHit at_exit;
    at_exit.range_m = 0.0;
    at_exit.cos_incidence = 1.0;
    const double sigma_p = sim.echo_sigma_ns(at_exit);  // no footprint: the pulse's own
    std::size_t compared = 0;
    for (std::size_t j = 0; j < samples.size(); ++j) {
        if (samples[j].cell_sigma == 0.0) {
            EXPECT_EQ(got[j], sigma_p) << j;
            continue;
        }
        if (samples[j].cell_sigma != beam_cell_sigma) {
            continue;  // a probe's spread: echo_sigma_ns(hit) takes the beam's
        }
        const double want = sim.echo_sigma_ns(samples[j].hit);
        EXPECT_TRUE(std::bit_cast<std::uint64_t>(got[j]) == std::bit_cast<std::uint64_t>(want) ||
                    (std::isnan(got[j]) && std::isnan(want)))
            << "sample " << j << ": " << got[j] << " vs " << want;
        ++compared;
    }
    EXPECT_GT(compared, 150u);
}

TEST(EchoSigmas, LanesBitForBitOneByOne) {
    expect_sigmas_match(0.0);
}

TEST(EchoSigmas, WithExitDiameterOneByOne) {
    expect_sigmas_match(0.01);
}

}  // namespace
}  // namespace beamtrace
