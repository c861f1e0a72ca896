// Fog as a soft target: the medium extinguishes the beam and scatters part of it back, so the
// received waveform holds, besides the hard targets' echoes, the fog's own echo near the sensor.
//
// The monostatic LiDAR equation for a volume (soft) target, with the pulse shape p(t) (peak 1):
//
//   P_r(t) = P_t eta A_r  integral_0^R_end  beta xi(r) exp(-2 alpha r) / r^2  p(t - 2 r / c)  dr
//
// beta the volume backscatter coefficient [1/(m sr)], xi(r) the overlap of the transmitter's
// beam and the receiver's field of view (0 close to the sensor, 1 from full_m on), alpha the
// extinction [1/m] of everything along the path (air, fog, rain), A_r the receiver area [m^2],
// eta the system efficiency, R_end the end of the path (the hard target that stops the beam or
// the last range considered). For a rectangular pulse of length tau this is the textbook
// P_t eta A_r beta (c tau / 2) exp(-2 alpha R) / R^2.
//
// Fog from its meteorological optical range (MOR, WMO: the path over which a collimated beam
// keeps 5 % of its flux): alpha = ln(20) / MOR. In fog the droplets are large against near-
// infrared wavelengths, so alpha hardly depends on the wavelength (Rasshofer, Spies and Spies,
// Adv. Radio Sci. 9, 2011). The backscatter coefficient beta = 0.046 / MOR [1/(m sr)] is the
// value for advection fog of Rasshofer et al. 2011 as used by Hahner et al. (ICCV 2021, "Fog
// simulation on real LiDAR point clouds"). Both can be overridden.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "beamtrace/physics/waveform.hpp"

namespace beamtrace {

/// How much of the beam the receiver sees at range r: 0 up to start_m, rising linearly to 1 at
/// full_m, 1 beyond (a biaxial sensor's blind zone and overlap region). start_m > 0: a ramp from
/// r = 0 would make the fog's echo (xi / r^2 ~ 1 / r) infinite. The defaults are those of a
/// typical automotive sensor; set them from your sensor's blind zone.
struct OverlapConfig {
    double start_m = 0.5;  ///< the receiver sees nothing of the beam closer than this [m]
    double full_m = 2.0;   ///< full overlap from here on [m], > start_m
    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// xi(r) of the header comment.
[[nodiscard]] double overlap_fraction(const OverlapConfig& overlap, double range_m);

struct FogConfig {
    double mor_m = 0.0;  ///< meteorological optical range [m], > 0
    /// alpha of the fog [1/m]; unset: ln(20) / mor_m.
    std::optional<double> extinction_per_m;
    /// beta of the fog [1/(m sr)]; unset: 0.046 / mor_m.
    std::optional<double> backscatter_per_m_sr;
    /// Every problem with these settings; empty when valid.
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// alpha of the fog [1/m].
[[nodiscard]] double fog_extinction_per_m(const FogConfig& fog);
/// beta of the fog [1/(m sr)].
[[nodiscard]] double fog_backscatter_per_m_sr(const FogConfig& fog);

/// A uniform soft target seen by one beam (or one sub-ray of it).
struct SoftTarget {
    double backscatter_per_m_sr = 0.0;  ///< beta of the medium
    double extinction_per_m = 0.0;      ///< alpha of the whole path (two-way: exp(-2 alpha r))
    OverlapConfig overlap;
};

/// How finely the soft target's integral is sampled, and where it stops.
struct SoftTargetSampling {
    double slab_m = 0.05;  ///< thickness of one slab [m]; half of c sigma_p / 2 or finer
    /// Thickness within the overlap ramp, where xi / r^2 bends sharply [m]; 0: slab_m.
    double ramp_slab_m = 0.0;
    /// Slabs whose peak power falls below this [W] beyond full overlap end the sum (the
    /// integrand only falls from there on): a fraction of the detection threshold.
    double cutoff_w = 0.0;
};

/// Appends the soft target's echo to `out` as one contribution per slab of the path from
/// overlap.start_m to end_m: a slab [r - d/2, r + d/2] adds a pulse of peak power
/// emitted_power_w * receiver_gain * beta * xi(r) * exp(-2 alpha r) / r^2 * d at range r,
/// receiver_gain being eta A_r [m^2]. This is the midpoint rule of the header's integral; its
/// error is far below 1 % when the slab is a small fraction of the pulse length.
void add_soft_target_echo(const SoftTarget& medium, double emitted_power_w, double receiver_gain_m2,
                          double end_m, const SoftTargetSampling& sampling,
                          std::vector<EchoContribution>& out);

/// A share of the beam (a sub-ray's weight) and where its path ends (its hard target's range,
/// or the last range considered when it meets nothing).
struct BeamShare {
    double weight = 1.0;
    double end_m = 0.0;
};

/// The same for a beam whose shares end at different ranges: the slab at r is weighted by the
/// sum of the weights of the shares still travelling at r (the hard targets shadow the fog
/// behind them). `shares` is sorted by end in place (no allocation per pulse).
void add_soft_target_echo(const SoftTarget& medium, double emitted_power_w, double receiver_gain_m2,
                          std::span<BeamShare> shares, const SoftTargetSampling& sampling,
                          std::vector<EchoContribution>& out);

/// What SoftTargetProfile::echo gives besides its contributions: the leading slabs, already
/// summed on the waveform's bin grid (BinnedEcho, waveform.hpp), and how to weigh them.
struct SoftTargetEcho {
    BinnedEcho binned;      ///< the leading slabs' samples
    std::size_t slabs = 0;  ///< how many leading slabs `binned` holds
    double scale_w = 0.0;   ///< emitted power x gain x beta x the travelling weight
    void clear() {
        binned.clear();
        slabs = 0;
        scale_w = 0.0;
    }
};

/// add_soft_target_echo for a whole survey, with its slabs and their pulses on the waveform's
/// bin grid worked out once. Its slabs run on a fixed grid from overlap.start_m until a share
/// ends; up to there a pulse's echo is one weight times a precomputed sum per bin (prefix
/// sums over the slabs that reach each bin), so a pulse costs one multiply-add per bin instead
/// of a Gaussian per slab. From where the first share ends on, slabs are cut as
/// add_soft_target_echo cuts them and returned as contributions. The slabs, their powers and
/// where the sum stops are those of add_soft_target_echo; only the order of the additions
/// differs (the samples agree to rounding).
class SoftTargetProfile {
  public:
    SoftTargetProfile() = default;
    /// Precomputes the slabs from overlap.start_m up to where a beam of weight `max_weight`
    /// meets the cut-off, at most `max_range_m` (and at most 2^16 slabs; any further ones are
    /// made per pulse).
    SoftTargetProfile(const SoftTarget& medium, double emitted_power_w, double receiver_gain_m2,
                      const SoftTargetSampling& sampling, const WaveformConfig& waveform,
                      double max_range_m, double max_weight = 1.5);

    [[nodiscard]] bool empty() const { return slabs_.empty(); }
    /// The echo of add_soft_target_echo(shares): the leading slabs into `binned`, the others
    /// appended to `out`. `shares` is sorted by end in place.
    void echo(std::span<BeamShare> shares, SoftTargetEcho& binned,
              std::vector<EchoContribution>& out) const;
    /// Sum over the binned slabs of their peak power / sigma_m x exp(-((r - range_m) /
    /// sigma_m)^2 / 2): what they add at an echo's peak at `range_m` (pulse.cpp's share of the
    /// medium), with slabs beyond 12 sigma_m left out (below 1e-31 of the nearest).
    [[nodiscard]] double share_at(const SoftTargetEcho& binned, double range_m,
                                  double sigma_m) const;

  private:
    struct Slab {
        double lo = 0.0, hi = 0.0, width = 0.0, r = 0.0, xi = 0.0, transmission = 0.0;
        double unit_w = 0.0;  ///< width xi transmission / r^2: the power per unit scale
    };
    /// True when slab `s` with the weight's scale `scale_w` ends the sum (add_soft_target_echo's
    /// cut-off test).
    [[nodiscard]] bool below_cutoff(std::size_t s, double scale_w) const;
    /// The bins' prefix sums of the slabs' unit pulses.
    void bin_slabs(const WaveformConfig& waveform);
    /// The first `n` slabs at `scale_w` into `binned`.
    void fill_bins(std::size_t n, double scale_w, SoftTargetEcho& binned) const;

    SoftTarget medium_;
    double emitted_power_w_ = 0.0, receiver_gain_m2_ = 0.0;
    SoftTargetSampling sampling_;
    double bin_ns_ = 0.5;
    std::vector<Slab> slabs_;
    std::size_t first_full_ = 0;  ///< the first slab beyond full overlap (r > full_m)
    std::int64_t first_bin_ = 0;  ///< the first bin any slab reaches
    std::vector<std::uint32_t> bin_first_slab_;  ///< per bin: the first slab reaching it
    std::vector<std::uint32_t> bin_offset_;      ///< per bin: where its prefix sums start
    std::vector<std::uint32_t> slab_last_bin_;   ///< per slab: the last bin it reaches - first_bin_
    std::vector<std::uint32_t> slab_first_bin_;  ///< per slab: its first bin - first_bin_
    std::vector<double> whole_;   ///< per bin: the sum over all its slabs (its last prefix sum)
    std::vector<double> prefix_;  ///< per bin: 0, then the sums over 1, 2, ... of its slabs
};

}  // namespace beamtrace
