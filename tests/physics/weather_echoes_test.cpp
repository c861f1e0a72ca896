// The weather's echo detection in groups (weather_echoes.hpp) against the whole waveform's, brute
// force: the same echoes within the documented bounds, pulse by pulse.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/physics/weather.hpp"
#include "beamtrace/physics/weather_echoes.hpp"
#include "beamtrace/physics/weather_medium.hpp"

namespace beamtrace {
namespace {

/// The bounds of docs/weather.md ("Detection in groups"): the echoes' energies (their samples)
/// within 1e-6; their fits' range, amplitude and width move where a neighbour below the
/// threshold is taken off as the pulse through its top instead of its fit.
constexpr double kRangeTolerance_m = 0.1;
constexpr double kAmplitudeTolerance = 0.4;  ///< relative
constexpr double kWidthTolerance = 0.4;      ///< relative
constexpr double kPowerTolerance = 1e-6;     ///< energy (equivalent power), relative
/// With the resolved split of rain and snow (kResolvedReachSigmas, docs/weather.md, "Resolved
/// particles") energy moves between neighbouring echoes: each within this fraction of the
/// pulse's echoes' total energy.
constexpr double kResolvedPowerOfTotal = 2e-3;
/// Pulses with another number of echoes (an echo whose top sample is below the threshold and
/// whose fit is not), at most this fraction.
constexpr double kOtherCountFraction = 5e-3;

/// What the comparisons saw.
struct Tally {
    std::size_t pulses_with_echoes = 0, echoes = 0, split = 0, other_count = 0;
    double worst_power = 0.0, worst_power_of_total = 0.0, worst_range = 0.0, worst_amplitude = 0.0,
           worst_width = 0.0;
};

/// Expects `groups` to be `whole` within the bounds; `power_of_total`: the energies also within
/// that fraction of the pulse's total.
void expect_same_echoes(const std::vector<Echo>& whole, const std::vector<Echo>& groups,
                        Tally& tally, double power_of_total = 0.0) {
    if (whole.size() != groups.size()) {
        ++tally.other_count;  // an echo at the threshold, on either side of it
        return;
    }
    double total_w = 0.0;
    for (const Echo& e : whole) {
        total_w += e.power_w;
    }
    for (std::size_t e = 0; e < whole.size(); ++e) {
        const Echo& a = whole[e];
        const Echo& b = groups[e];
        EXPECT_NEAR(b.range_m, a.range_m, kRangeTolerance_m);
        EXPECT_NEAR(b.amplitude_w, a.amplitude_w, kAmplitudeTolerance * a.amplitude_w);
        EXPECT_NEAR(b.width_ns, a.width_ns, kWidthTolerance * a.width_ns);
        EXPECT_NEAR(b.power_w, a.power_w,
                    std::max(kPowerTolerance * a.power_w, power_of_total * total_w));
        tally.worst_power = std::max(tally.worst_power, std::abs(b.power_w / a.power_w - 1.0));
        tally.worst_power_of_total =
            std::max(tally.worst_power_of_total, std::abs(b.power_w - a.power_w) / total_w);
        tally.worst_range = std::max(tally.worst_range, std::abs(b.range_m - a.range_m));
        tally.worst_amplitude =
            std::max(tally.worst_amplitude, std::abs(b.amplitude_w / a.amplitude_w - 1.0));
        tally.worst_width = std::max(tally.worst_width, std::abs(b.width_ns / a.width_ns - 1.0));
    }
    tally.pulses_with_echoes += whole.empty() ? 0 : 1;
    tally.echoes += whole.size();
}

void report(const Tally& t) {
    ::testing::Test::RecordProperty("worst_relative_power", std::to_string(t.worst_power));
    ::testing::Test::RecordProperty("worst_range_m", std::to_string(t.worst_range));
    ::testing::Test::RecordProperty("worst_relative_amplitude", std::to_string(t.worst_amplitude));
    ::testing::Test::RecordProperty("worst_relative_width", std::to_string(t.worst_width));
    std::printf(
        "other counts %zu; pulses with echoes %zu, echoes %zu, split %zu; worst: power %.3g (of "
        "the "
        "total %.3g), range %.3g m, amplitude %.3g, width %.3g\n",
        t.other_count, t.pulses_with_echoes, t.echoes, t.split, t.worst_power,
        t.worst_power_of_total, t.worst_range, t.worst_amplitude, t.worst_width);
}

/// A pulse's sub-ray hits: a tilted wall between 2 and 60 m (ranges spread along the beam), or
/// the sky for one pulse in five.
std::vector<SubRayHit> random_hits(std::mt19937_64& gen, std::size_t n) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<SubRayHit> hits(n);
    if (unit(gen) < 0.2) {
        return hits;  // misses
    }
    const double range = 2.0 + 58.0 * unit(gen), tilt = 0.05 * unit(gen);
    const double cos_i = 0.2 + 0.8 * unit(gen), albedo = 0.05 + 0.6 * unit(gen);
    for (std::size_t j = 0; j < n; ++j) {
        hits[j].range_m = range * (1.0 + tilt * (unit(gen) - 0.5));
        hits[j].cos_incidence = cos_i;
        hits[j].albedo = albedo;
    }
    return hits;
}

/// The examples' sensor (docs/weather.md): 30 W, 20 nW, 3 mrad, 7 sub-rays.
PhysicsConfig weather_sensor() {
    PhysicsConfig c;
    c.radiometry.peak_power_w = 30.0;
    c.radiometry.detection_threshold_w = 2e-8;
    c.beam.divergence_rad = 3e-3;
    c.beam.rings = 1;
    c.beam.exit_diameter_m = 0.01;
    c.max_returns = 15;
    c.weather.emplace();
    return c;
}

/// Simulates `pulses` pulses of `c` with the whole waveform (keep_waveform: the detection of
/// waveform.hpp) and in groups, and compares every echo (`power_of_total`: expect_same_echoes).
Tally compare_pulses(PhysicsConfig c, int pulses, double power_of_total = 0.0) {
    c.keep_waveform = true;
    const PulseSimulator whole(c);
    c.keep_waveform = false;
    const PulseSimulator groups(c);
    std::mt19937_64 gen(23);
    PulseResponse a, b;
    Tally tally;
    for (int i = 0; i < pulses; ++i) {
        const auto hits = random_hits(gen, whole.sub_ray_count());
        whole.simulate(4, static_cast<std::uint64_t>(i), hits, a);
        groups.simulate(4, static_cast<std::uint64_t>(i), hits, b);
        expect_same_echoes(a.echoes, b.echoes, tally, power_of_total);
        if (::testing::Test::HasFailure()) {
            ADD_FAILURE() << "pulse " << i;
            break;
        }
        // The returns follow from the echoes: their weather marks too.
        for (std::size_t r = 0;
             a.echoes.size() == b.echoes.size() && r < std::min(a.returns.size(), b.returns.size());
             ++r) {
            EXPECT_EQ(a.returns[r].weather, b.returns[r].weather);
            EXPECT_EQ(a.returns[r].sub_ray, b.returns[r].sub_ray);
        }
        // The whole waveform is 0 somewhere between two of its echoes: the groups split there.
        const auto& y = a.waveform.samples_w;
        const auto first = std::find_if(y.begin(), y.end(), [](double v) { return v > 0; });
        const auto gap = std::find(first, y.end(), 0.0);
        tally.split += std::any_of(gap, y.end(), [](double v) { return v > 0; }) ? 1 : 0;
    }
    EXPECT_LE(static_cast<double>(tally.other_count), kOtherCountFraction * pulses);
    return tally;
}

TEST(WeatherEchoes, GroupsGiveTheWholeWaveformsEchoesInRain) {
    PhysicsConfig c = weather_sensor();
    c.weather->precipitation = PrecipitationConfig{PrecipitationKind::rain, 25.0, {}, 0.25};
    // Rain without fog: the resolved split (kResolvedReachSigmas).
    const WeatherMedium rain(*c.weather, c.radiometry, c.beam, c.waveform,
                             weather_extinction_per_m(*c.weather));
    ASSERT_EQ(rain.group_reach_sigmas(), kResolvedReachSigmas);
    const Tally t = compare_pulses(c, 20000, kResolvedPowerOfTotal);
    EXPECT_GT(t.pulses_with_echoes, 15000u);
    EXPECT_GT(t.echoes, 25000u);  // the targets' and the drops'
    EXPECT_GT(t.split, 5000u);    // pulses whose groups were detected apart
    report(t);
}

TEST(WeatherEchoes, GroupsGiveTheWholeWaveformsEchoesInFogAndSnow) {
    PhysicsConfig c = weather_sensor();
    c.weather->fog = FogConfig{200.0, {}, {}};
    c.weather->precipitation = PrecipitationConfig{PrecipitationKind::snow, 2.0, {}, 0.25};
    c.waveform.bin_ns = 1.0;  // coarser bins: closed forms and fits still agree
    // With fog the exact split (the fog's slabs are one echo).
    const WeatherMedium fog(*c.weather, c.radiometry, c.beam, c.waveform,
                            weather_extinction_per_m(*c.weather));
    ASSERT_EQ(fog.group_reach_sigmas(), kExactReachSigmas);
    const Tally t = compare_pulses(c, 5000);
    EXPECT_GT(t.pulses_with_echoes, 3000u);
    report(t);
}

/// A pulse alone: the closed form is the sampled fit's answer, at any bin offset and stretch.
TEST(WeatherEchoes, LonePulseInClosedFormIsItsSampledFit) {
    WaveformConfig config;
    std::mt19937_64 gen(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const BinnedEcho none;
    Tally tally;
    for (int i = 0; i < 2000; ++i) {
        const double sigma_p = config.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
        const EchoContribution c{1.0 + 100.0 * unit(gen), 1e-8 * std::exp(10.0 * unit(gen)),
                                 unit(gen) < 0.5 ? 0.0 : sigma_p * (1.0 + 3.0 * unit(gen))};
        Waveform w;
        build_waveform(config, std::span(&c, 1), w);
        std::vector<Echo> whole, groups;
        detect_echoes(config, w, 1e-12, whole);
        detect_echoes_in_groups(config, std::span(&c, 1), none, 1e-12, groups);
        ASSERT_EQ(whole.size(), 1u);
        expect_same_echoes(whole, groups, tally);
        // The energy in closed form: the Gaussian's share inside the sampled record (without
        // that share, 5.7e-7 too high), the trapezoid's error 1.1e-7 at sigma of 3.4 bins.
        ASSERT_EQ(groups.size(), 1u);
        EXPECT_NEAR(groups[0].power_w, whole[0].power_w, 3e-7 * whole[0].power_w);
    }
    report(tally);
}

// Faint pulses, each below the threshold, a few pulse widths apart (one group): the groups skip
// those whose summed waveform provably stays below the threshold, and give the whole waveform's
// echoes bit for bit otherwise (one group is the whole waveform, its unfitted spans below the
// threshold). Both cases occur.
TEST(WeatherEchoes, FaintPulsesApartGiveTheWholeWaveformsEchoesExactly) {
    WaveformConfig config;
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const BinnedEcho none;
    const double threshold_w = 1e-8;
    std::size_t below = 0, reaching = 0;
    for (int i = 0; i < 20000; ++i) {
        std::vector<EchoContribution> pulses;
        double range_m = 2.0 + 40.0 * unit(gen);
        const int n = 2 + static_cast<int>(3.0 * unit(gen));
        for (int k = 0; k < n; ++k) {
            pulses.push_back({range_m, threshold_w * (0.3 + 0.69 * unit(gen)), 0.0});
            range_m += 0.2 + 1.0 * unit(gen);
        }
        Waveform w;
        build_waveform(config, pulses, w);
        const double highest_w = *std::max_element(w.samples_w.begin(), w.samples_w.end());
        (highest_w < threshold_w ? below : reaching) += 1;
        std::vector<Echo> whole, groups;
        detect_echoes(config, w, threshold_w, threshold_w, whole);
        detect_echoes_in_groups(config, pulses, none, threshold_w, groups);
        ASSERT_EQ(whole.size(), groups.size()) << "pulse set " << i;
        for (std::size_t e = 0; e < whole.size(); ++e) {
            EXPECT_EQ(groups[e].range_m, whole[e].range_m);
            EXPECT_EQ(groups[e].amplitude_w, whole[e].amplitude_w);
            EXPECT_EQ(groups[e].width_ns, whole[e].width_ns);
            EXPECT_EQ(groups[e].power_w, whole[e].power_w);
        }
        if (highest_w < threshold_w) {
            EXPECT_TRUE(whole.empty());
        }
    }
    EXPECT_GT(below, 1000u);
    EXPECT_GT(reaching, 1000u);
}

/// What separate detection of resolved pulses may change against their detection together
/// (docs/weather.md, "Resolved particles"): each echo is then its own pulse.
constexpr double kResolvedRangeTolerance_m = 1e-5;
constexpr double kResolvedAmplitudeTolerance = 1e-5;  ///< relative
constexpr double kResolvedPowerTolerance = 1e-3;  ///< relative, times (1 + the other's / its peak)

// Two drops whose 2-sigma reaches leave the least separation between them: at
// kResolvedReachSigmas each is its own group and its echo is its pulse, exactly; detected
// together (kExactReachSigmas, the whole waveform's answer) they give the same echoes within the
// documented bounds.
TEST(WeatherEchoes, ResolvedPulsesAreDetectedApartAsTheirPulses) {
    WaveformConfig config;
    const double sigma_ns = config.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    const double least_m =
        (2.0 * kResolvedReachSigmas * sigma_ns + 4.0 * config.bin_ns) / round_trip_ns_per_m() +
        config.min_separation_or_default_m();
    std::mt19937_64 gen(17);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const BinnedEcho none;
    const double threshold_w = 1e-8;
    double worst_range = 0.0, worst_amplitude = 0.0, worst_power = 0.0;
    std::size_t fitted_apart = 0;
    for (int i = 0; i < 2000; ++i) {
        const double r0 = 1.0 + 40.0 * unit(gen), r1 = r0 + least_m * (1.0 + unit(gen));
        const std::vector<EchoContribution> pulses{
            {r0, 1.1 * threshold_w * std::exp(3.0 * unit(gen)), 0.0},
            {r1, 1.1 * threshold_w * std::exp(3.0 * unit(gen)), 0.0}};
        std::vector<Echo> apart, together;
        detect_echoes_in_groups(config, pulses, none, threshold_w, apart, kResolvedReachSigmas);
        detect_echoes_in_groups(config, pulses, none, threshold_w, together, kExactReachSigmas);
        ASSERT_EQ(apart.size(), 2u);
        ASSERT_EQ(together.size(), 2u);
        for (std::size_t e = 0; e < 2; ++e) {
            EXPECT_EQ(apart[e].range_m, pulses[e].range_m);
            EXPECT_EQ(apart[e].amplitude_w, pulses[e].power_w);
            EXPECT_NEAR(apart[e].width_ns, config.pulse_fwhm_ns, 1e-12);
            EXPECT_NEAR(apart[e].power_w, pulses[e].power_w, 1e-6 * pulses[e].power_w);
            const double other = pulses[1 - e].power_w / pulses[e].power_w;
            EXPECT_NEAR(together[e].range_m, apart[e].range_m, kResolvedRangeTolerance_m);
            EXPECT_NEAR(together[e].amplitude_w, apart[e].amplitude_w,
                        kResolvedAmplitudeTolerance * apart[e].amplitude_w);
            EXPECT_NEAR(together[e].power_w, apart[e].power_w,
                        kResolvedPowerTolerance * (1.0 + other) * apart[e].power_w);
            worst_range = std::max(worst_range, std::abs(together[e].range_m - apart[e].range_m));
            worst_amplitude = std::max(
                worst_amplitude, std::abs(together[e].amplitude_w / apart[e].amplitude_w - 1.0));
            worst_power =
                std::max(worst_power,
                         std::abs(together[e].power_w / apart[e].power_w - 1.0) / (1.0 + other));
            fitted_apart += together[e].range_m != apart[e].range_m ? 1 : 0;
        }
    }
    // Together, the fits see the other's tail: the two paths differ.
    EXPECT_GT(fitted_apart, 100u);
    std::printf("worst: range %.3g m, amplitude %.3g, power %.3g (per 1 + other / own)\n",
                worst_range, worst_amplitude, worst_power);
}

}  // namespace
}  // namespace beamtrace
