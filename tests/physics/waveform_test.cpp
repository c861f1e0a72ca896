#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/physics/waveform.hpp"
#include "physics/detail/fast_log.hpp"

namespace beamtrace {
namespace {

std::vector<Echo> echoes_of(const std::vector<EchoContribution>& c, double threshold = 1e-12,
                            WaveformConfig cfg = {}) {
    Waveform w;
    build_waveform(cfg, c, w);
    std::vector<Echo> out;
    detect_echoes(cfg, w, threshold, out);
    return out;
}

TEST(PhysicsWaveform, SingleEchoIsRecoveredExactly) {
    // Off the bin grid on purpose.
    const auto e = echoes_of({{30.0123, 2e-6}});
    ASSERT_EQ(e.size(), 1u);
    EXPECT_NEAR(e[0].range_m, 30.0123, 1e-9);
    EXPECT_NEAR(e[0].amplitude_w, 2e-6, 1e-15);
    EXPECT_NEAR(e[0].width_ns, 4.0, 1e-9);
    EXPECT_NEAR(e[0].power_w, 2e-6, 1e-6 * 2e-6);  // 5-sigma truncation: 6e-7
    EXPECT_TRUE(echoes_of({{30.0, 2e-6}}, 3e-6).empty());
    EXPECT_TRUE(echoes_of({}).empty());
}

TEST(PhysicsWaveform, SamplesAreTheGaussianPulse) {
    WaveformConfig cfg;
    cfg.pulse_fwhm_ns = 3.0;
    cfg.bin_ns = 0.25;
    Waveform w;
    build_waveform(cfg, std::vector<EchoContribution>{{15.0, 1.0}}, w);
    const double t0 = 15.0 * round_trip_ns_per_m();  // 100.07 ns
    const double sigma = 3.0 / (2 * std::sqrt(2 * std::log(2.0)));
    ASSERT_GT(w.samples_w.size(), 40u);
    EXPECT_LE(w.time_ns(0), t0 - 5 * sigma);
    EXPECT_GE(w.time_ns(w.samples_w.size() - 1), t0 + 5 * sigma);
    for (std::size_t k = 0; k < w.samples_w.size(); ++k) {
        const double dt = w.time_ns(k) - t0;
        const double expected =
            std::abs(dt) <= 5 * sigma ? std::exp(-dt * dt / (2 * sigma * sigma)) : w.samples_w[k];
        EXPECT_NEAR(w.samples_w[k], expected, 1e-12) << k;
    }
    // Half maximum at +-FWHM / 2.
    const double half = std::exp(-(1.5 * 1.5) / (2 * sigma * sigma));
    EXPECT_NEAR(half, 0.5, 1e-12);
}

TEST(PhysicsWaveform, TwoSeparatedEchoesAndMergedOnes) {
    // 1 m apart (6.7 ns, well above the 4 ns pulse): two echoes at the right ranges.
    const auto two = echoes_of({{30.0, 1e-6}, {31.0, 0.5e-6}});
    ASSERT_EQ(two.size(), 2u);
    EXPECT_NEAR(two[0].range_m, 30.0, 0.01);
    EXPECT_NEAR(two[1].range_m, 31.0, 0.01);
    EXPECT_NEAR(two[0].amplitude_w, 1e-6, 0.02e-6);
    EXPECT_NEAR(two[1].amplitude_w, 0.5e-6, 0.02e-6);
    // 0.3 m apart, below c sigma = 0.51 m: one echo between them, wider than the pulse.
    const auto merged = echoes_of({{30.0, 1e-6}, {30.3, 1e-6}});
    ASSERT_EQ(merged.size(), 1u);
    EXPECT_NEAR(merged[0].range_m, 30.15, 1e-3);  // symmetric
    EXPECT_GT(merged[0].width_ns, 4.2);
    EXPECT_NEAR(merged[0].power_w, 2e-6, 1e-6 * 2e-6);  // energy is kept
    // Just above the resolution limit (c FWHM / 2 = 0.6 m, a dip of 10 %) two equal echoes
    // separate; just below it they merge.
    EXPECT_EQ(echoes_of({{30.0, 1e-6}, {30.65, 1e-6}}).size(), 2u);
    EXPECT_EQ(echoes_of({{30.0, 1e-6}, {30.6, 1e-6}}).size(), 1u);
}

TEST(PhysicsWaveform, StretchedEchoIsFittedExactlyWithItsEnergy) {
    // A contribution of sigma 10 ns (a 23.5 ns FWHM echo): peak P sigma_p / sigma.
    const double sigma_p = 4.0 / (2 * std::sqrt(2 * std::log(2.0)));
    const auto e = echoes_of({{500.0123, 3e-7, 10.0}});
    ASSERT_EQ(e.size(), 1u);
    EXPECT_NEAR(e[0].range_m, 500.0123, 1e-9);
    EXPECT_NEAR(e[0].amplitude_w, 3e-7 * sigma_p / 10.0, 1e-9 * 3e-7);
    EXPECT_NEAR(e[0].width_ns, 10.0 * 2 * std::sqrt(2 * std::log(2.0)), 1e-9);
    EXPECT_NEAR(e[0].power_w, 3e-7, 1e-6 * 3e-7);  // energy kept
    // The window reaches 5 sigma of the widest contribution.
    WaveformConfig cfg;
    Waveform w;
    build_waveform(cfg, std::vector<EchoContribution>{{500.0, 1.0, 10.0}, {501.0, 1.0}}, w);
    EXPECT_LE(w.time_ns(0), 500.0 * round_trip_ns_per_m() - 50.0);
    EXPECT_GE(w.time_ns(w.samples_w.size() - 1), 501.0 * round_trip_ns_per_m() + 50.0);
}

TEST(PhysicsWaveform, SeparationAndDipDecideWhetherPeaksSplit) {
    // 1 m apart with a deep dip: two echoes; a minimum separation of 1.5 m merges them into
    // one carrying both energies.
    EXPECT_EQ(echoes_of({{30.0, 1e-6}, {31.0, 0.5e-6}}).size(), 2u);
    WaveformConfig far;
    far.min_separation_m = 1.5;
    const auto merged = echoes_of({{30.0, 1e-6}, {31.0, 0.5e-6}}, 1e-12, far);
    ASSERT_EQ(merged.size(), 1u);
    EXPECT_NEAR(merged[0].power_w, 1.5e-6, 1e-5 * 1.5e-6);
    EXPECT_GT(merged[0].width_ns, 4.5);  // one wide echo
    // 0.65 m apart: a dip of 14.7 %; a required dip of 20 % merges them.
    WaveformConfig deep;
    deep.min_dip = 0.2;
    EXPECT_EQ(echoes_of({{30.0, 1e-6}, {30.65, 1e-6}}, 1e-12, deep).size(), 1u);
    deep.min_dip = 0.0;
    EXPECT_EQ(echoes_of({{30.0, 1e-6}, {30.65, 1e-6}}, 1e-12, deep).size(), 2u);
    // A weak echo well apart is its own echo (and dropped below the threshold alone).
    const auto weak = echoes_of({{30.0, 1e-6}, {40.0, 1e-9}});
    ASSERT_EQ(weak.size(), 2u);
    EXPECT_NEAR(weak[1].amplitude_w, 1e-9, 1e-12);
    EXPECT_EQ(echoes_of({{30.0, 1e-6}, {40.0, 1e-9}}, 1e-8).size(), 1u);
    // The automatic separation is c FWHM / 4.
    EXPECT_NEAR(WaveformConfig{}.min_separation_or_default_m(), 0.2998, 1e-4);
    EXPECT_EQ(far.min_separation_or_default_m(), 1.5);
}

TEST(PhysicsWaveform, ValidateBins) {
    WaveformConfig c;
    EXPECT_TRUE(c.validate().empty());
    c.bin_ns = 3.0;
    EXPECT_EQ(c.validate().size(), 1u);
    c.pulse_fwhm_ns = -1;
    EXPECT_EQ(c.validate().size(), 2u);
    c = WaveformConfig{};
    c.min_dip = 1.0;
    c.min_separation_m = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(c.validate().size(), 2u);
}

/// The 19 sub-rays of a beam along +x from the origin against a step: the plane x = near_m
/// where y > edge_y_m, the plane x = far_m elsewhere (both facing the sensor).
std::vector<SubRayHit> step_hits(const PulseSimulator& sim, double near_m, double far_m,
                                 double edge_y_m) {
    std::vector<Vec3d> dirs(sim.sub_ray_count());
    sim.sub_ray_directions(1, 0, {1, 0, 0}, dirs);
    std::vector<SubRayHit> hits;
    for (const auto& d : dirs) {
        SubRayHit h;
        h.albedo = 0.4;
        h.cos_incidence = d.x;
        h.range_m = near_m / d.x;
        if (h.range_m * d.y <= edge_y_m) {
            h.range_m = far_m / d.x;
        }
        hits.push_back(h);
    }
    return hits;
}

PhysicsConfig beam_config(ReturnMode mode) {
    PhysicsConfig c;
    c.beam.divergence_rad = 3e-3;  // footprint radius 3 cm at 20 m
    c.return_mode = mode;
    return c;
}

// Acceptance: a footprint straddling a step edge between planes 1 m apart gives two returns at
// their ranges; a single plane gives one.
TEST(PhysicsWaveform, StepEdgeGivesTwoReturns) {
    const PulseSimulator sim(beam_config(ReturnMode::all));
    ASSERT_EQ(sim.sub_ray_count(), 19u);
    PulseResponse r;
    sim.simulate(1, 0, step_hits(sim, 20.0, 21.0, 0.0), r);
    ASSERT_EQ(r.returns.size(), 2u);
    EXPECT_NEAR(r.returns[0].range_m, 20.0, 0.01);
    EXPECT_NEAR(r.returns[1].range_m, 21.0, 0.01);
    EXPECT_EQ(r.returns[0].return_number, 1);
    EXPECT_EQ(r.returns[1].return_number, 2);
    EXPECT_EQ(r.returns[0].number_of_returns, 2);
    EXPECT_EQ(r.returns[1].number_of_returns, 2);
    // The sub-ray named for each return hit that return's plane.
    const auto hits = step_hits(sim, 20.0, 21.0, 0.0);
    EXPECT_LT(hits[r.returns[0].sub_ray].range_m, 20.5);
    EXPECT_GT(hits[r.returns[1].sub_ray].range_m, 20.5);
    // The two returns share the pulse energy: their powers add up to the sub-rays' sum.
    double total = 0;
    for (const double p : r.sub_ray_power_w) {
        total += p;
    }
    EXPECT_NEAR(r.returns[0].power_w + r.returns[1].power_w, total, 0.02 * total);

    // The edge outside the footprint: one plane, one return.
    sim.simulate(1, 0, step_hits(sim, 20.0, 21.0, 1.0), r);
    ASSERT_EQ(r.returns.size(), 1u);
    EXPECT_NEAR(r.returns[0].range_m, 21.0, 0.01);
    sim.simulate(1, 0, step_hits(sim, 20.0, 21.0, -1.0), r);
    ASSERT_EQ(r.returns.size(), 1u);
    EXPECT_NEAR(r.returns[0].range_m, 20.0, 0.01);
    EXPECT_EQ(r.returns[0].number_of_returns, 1);
    // Planes closer than the resolution merge into one return between them.
    sim.simulate(1, 0, step_hits(sim, 20.0, 20.2, 0.0), r);
    ASSERT_EQ(r.returns.size(), 1u);
    EXPECT_GT(r.returns[0].range_m, 20.0);
    EXPECT_LT(r.returns[0].range_m, 20.2);
    EXPECT_GT(r.returns[0].echo_width_ns, 4.0);
}

TEST(PhysicsWaveform, ReturnModes) {
    // The edge at y = -1 cm: the near plane gets most of the footprint and the strongest echo.
    const auto run = [](ReturnMode mode, int max_returns) {
        PhysicsConfig c = beam_config(mode);
        c.max_returns = max_returns;
        const PulseSimulator sim(c);
        PulseResponse r;
        sim.simulate(1, 0, step_hits(sim, 20.0, 21.0, -0.01), r);
        return r;
    };
    const auto all = run(ReturnMode::all, 5);
    ASSERT_EQ(all.returns.size(), 2u);
    ASSERT_GT(all.returns[0].amplitude_w, all.returns[1].amplitude_w);
    const auto first = run(ReturnMode::first, 5);
    ASSERT_EQ(first.returns.size(), 1u);
    EXPECT_NEAR(first.returns[0].range_m, 20.0, 0.01);
    EXPECT_EQ(first.returns[0].number_of_returns, 1);
    const auto last = run(ReturnMode::last, 5);
    ASSERT_EQ(last.returns.size(), 1u);
    EXPECT_NEAR(last.returns[0].range_m, 21.0, 0.01);
    const auto strongest = run(ReturnMode::strongest, 5);
    ASSERT_EQ(strongest.returns.size(), 1u);
    EXPECT_NEAR(strongest.returns[0].range_m, 20.0, 0.01);
    EXPECT_EQ(strongest.echoes.size(), 2u);
    const auto capped = run(ReturnMode::all, 1);
    ASSERT_EQ(capped.returns.size(), 1u);
    EXPECT_NEAR(capped.returns[0].range_m, 20.0, 0.01);
    // All sub-rays missing: no returns, no waveform.
    const PulseSimulator sim(beam_config(ReturnMode::all));
    PulseResponse r;
    sim.simulate(1, 0, std::vector<SubRayHit>(sim.sub_ray_count()), r);
    EXPECT_TRUE(r.returns.empty());
    EXPECT_FALSE(r.dropped);
}

TEST(PhysicsWaveform, KeepsTheWaveformOnRequest) {
    PhysicsConfig c = beam_config(ReturnMode::all);
    c.keep_waveform = true;
    const PulseSimulator sim(c);
    PulseResponse r;
    sim.simulate(1, 0, step_hits(sim, 20.0, 21.0, 0.0), r);
    ASSERT_FALSE(r.waveform.samples_w.empty());
    EXPECT_EQ(r.waveform.bin_ns, 0.5);
    EXPECT_LT(r.waveform.time_ns(0), 20.0 * round_trip_ns_per_m());
    EXPECT_GT(r.waveform.time_ns(r.waveform.samples_w.size() - 1), 21.0 * round_trip_ns_per_m());
}

// The echo detection as documented in waveform.hpp, written plainly (every refit subtracts every
// other first fit at every sample): detect_echoes must give the same echoes bit for bit, with
// its shortcuts (refits whose neighbours provably change no sample, exps that change no bit).
namespace plain {

struct Fit {
    double centre_ns, amplitude, sigma_ns;
    [[nodiscard]] double at(double t) const {
        const double d = (t - centre_ns) / sigma_ns;
        return std::abs(d) > 38.7 ? 0.0 : amplitude * std::exp(-0.5 * d * d);
    }
};
struct Span {
    std::size_t lo, hi, top;
};

std::vector<Span> spans_of(const WaveformConfig& cfg, const std::vector<double>& y) {
    std::vector<Span> spans;
    const double min_sep = cfg.min_separation_or_default_m() * round_trip_ns_per_m() / cfg.bin_ns;
    std::size_t valley = 0;
    for (std::size_t k = 1; k + 1 < y.size(); ++k) {
        if (!spans.empty() && y[k] < y[valley]) {
            valley = k;
        }
        if (!(y[k] > y[k - 1] && y[k] >= y[k + 1])) {
            continue;
        }
        if (spans.empty()) {
            spans.push_back({0, y.size() - 1, k});
            valley = k;
        } else if (static_cast<double>(k - spans.back().top) >= min_sep &&
                   y[valley] < (1.0 - cfg.min_dip) * std::min(y[spans.back().top], y[k])) {
            spans.back().hi = valley;
            spans.push_back({valley, y.size() - 1, k});
            valley = k;
        } else if (y[k] > y[spans.back().top]) {
            spans.back().top = k;
            valley = k;
        }
    }
    return spans;
}

/// Caruana's parabola with Guo's weights over the samples v(m) >= 0.2 v(top) around the top.
template <typename V>
bool fit(const Waveform& w, const Span& s, V v, Fit& out) {
    const double peak = v(s.top);
    if (!(peak > 0)) {
        return false;
    }
    std::size_t a = s.top, b = s.top;
    while (a > s.lo && v(a - 1) >= 0.2 * peak) {
        --a;
    }
    while (b < s.hi && v(b + 1) >= 0.2 * peak) {
        ++b;
    }
    if (b - a < 2) {
        return false;
    }
    double S[5] = {0, 0, 0, 0, 0}, R[3] = {0, 0, 0};
    for (std::size_t m = a; m <= b; ++m) {
        const double t = static_cast<double>(m) - static_cast<double>(s.top);
        const double y = v(m), l = detail::fast_log(y / peak);  // the fit's log
        double tn = y * y;
        for (int n = 0; n < 5; ++n) {
            S[n] += tn;
            if (n < 3) {
                R[n] += tn * l;
            }
            tn *= t;
        }
    }
    const auto det = [](double a11, double a12, double a13, double a21, double a22, double a23,
                        double a31, double a32, double a33) {
        return a11 * (a22 * a33 - a23 * a32) - a12 * (a21 * a33 - a23 * a31) +
               a13 * (a21 * a32 - a22 * a31);
    };
    const double d = det(S[0], S[1], S[2], S[1], S[2], S[3], S[2], S[3], S[4]);
    const double c0 = det(R[0], S[1], S[2], R[1], S[2], S[3], R[2], S[3], S[4]) / d;
    const double c1 = det(S[0], R[0], S[2], S[1], R[1], S[3], S[2], R[2], S[4]) / d;
    const double c2 = det(S[0], S[1], R[0], S[1], S[2], R[1], S[2], S[3], R[2]) / d;
    const double vertex = -c1 / (2.0 * c2);
    const double lo = static_cast<double>(a) - static_cast<double>(s.top);
    const double hi = static_cast<double>(b) - static_cast<double>(s.top);
    if (!(c2 < 0) || !std::isfinite(c0) || !(vertex >= lo) || !(vertex <= hi)) {
        return false;
    }
    out = {w.time_ns(s.top) + vertex * w.bin_ns, peak * std::exp(c0 - c1 * c1 / (4.0 * c2)),
           w.bin_ns / std::sqrt(-2.0 * c2)};
    return true;
}

std::vector<Echo> echoes(const WaveformConfig& cfg, const Waveform& w, double threshold) {
    const auto& y = w.samples_w;
    const std::vector<Span> spans = spans_of(cfg, y);
    const double sigma_p = cfg.pulse_fwhm_ns / (2.0 * std::sqrt(2.0 * std::log(2.0)));
    const auto fit_of = [&](std::size_t e, const std::vector<Fit>& others) {
        Fit f{w.time_ns(spans[e].top), y[spans[e].top], sigma_p};
        const auto residual = [&](std::size_t m) {
            double v = y[m];
            for (std::size_t o = 0; o < others.size(); ++o) {
                v -= o == e ? 0.0 : others[o].at(w.time_ns(m));
            }
            return v;
        };
        if (!fit(w, spans[e], residual, f)) {
            f = {w.time_ns(spans[e].top), y[spans[e].top], sigma_p};
        }
        return f;
    };
    std::vector<Fit> first, fits;
    for (std::size_t e = 0; e < spans.size(); ++e) {
        first.push_back(fit_of(e, {}));
    }
    for (std::size_t e = 0; e < spans.size(); ++e) {
        fits.push_back(spans.size() > 1 ? fit_of(e, first) : first[e]);
    }
    std::vector<Echo> out;
    for (std::size_t e = 0; e < spans.size(); ++e) {
        if (fits[e].amplitude >= threshold) {
            double sum = 0.5 * (y[spans[e].lo] + y[spans[e].hi]);
            for (std::size_t j = spans[e].lo + 1; j < spans[e].hi; ++j) {
                sum += y[j];
            }
            out.push_back({fits[e].centre_ns / round_trip_ns_per_m(), fits[e].amplitude,
                           fits[e].sigma_ns * 2.0 * std::sqrt(2.0 * std::log(2.0)),
                           sum * w.bin_ns / (sigma_p * std::sqrt(2.0 * std::numbers::pi))});
        }
    }
    return out;
}

}  // namespace plain

TEST(PhysicsWaveform, DetectionEqualsThePlainRefitBitForBit) {
    // Echoes from 0.3 m to 8 m apart (a few sigma to far beyond the point where a neighbour's
    // fit no longer changes a bit of a sample) and from 1e-10 to 1e-5 W (1e5 apart), some
    // stretched: rain drops in front of a target.
    const WaveformConfig cfg;
    std::uint64_t state = 12345;
    const auto uniform = [&state] {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(state >> 11) * 0x1p-53;
    };
    std::size_t echoes = 0, multi = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::vector<EchoContribution> c;
        double r = 5.0 + 10.0 * uniform();
        const int n = 2 + static_cast<int>(5.0 * uniform());
        for (int j = 0; j < n; ++j) {
            r += 0.3 + 7.7 * uniform() * uniform();
            const double sigma = uniform() < 0.2 ? 1.7 + 3.0 * uniform() : 0.0;
            c.push_back({r, std::pow(10.0, -10.0 + 5.0 * uniform()), sigma});
        }
        Waveform w;
        build_waveform(cfg, c, w);
        const double threshold = std::pow(10.0, -10.0 + 4.0 * uniform());
        std::vector<Echo> got;
        detect_echoes(cfg, w, threshold, got);
        const std::vector<Echo> want = plain::echoes(cfg, w, threshold);
        ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
        for (std::size_t e = 0; e < got.size(); ++e) {
            EXPECT_EQ(got[e].range_m, want[e].range_m) << "trial " << trial << " echo " << e;
            EXPECT_EQ(got[e].amplitude_w, want[e].amplitude_w) << "trial " << trial;
            EXPECT_EQ(got[e].width_ns, want[e].width_ns) << "trial " << trial;
            EXPECT_EQ(got[e].power_w, want[e].power_w) << "trial " << trial;
        }
        echoes += got.size();
        multi += got.size() > 1 ? 1 : 0;
    }
    EXPECT_GT(echoes, 3000u);
    EXPECT_GT(multi, 300u);  // many waveforms with separate, refitted echoes
}

}  // namespace
}  // namespace beamtrace
