// Echo detection of a pulse that crosses a medium (docs/weather.md, "Detection in groups"):
// a rain or snow pulse's waveform holds a few particles' echoes metres before the scene's, and
// is 0 in between. Used by PulseSimulator for the weather's pulses.
#pragma once

#include <span>
#include <vector>

#include "beamtrace/physics/waveform.hpp"

namespace beamtrace {

/// Echo detection of a pulse that crosses a medium (docs/weather.md, "Detection in groups"): the
/// same echoes as build_waveform and detect_echoes on all of `contributions` and `binned`, found
/// group by group. Each contribution's pulse reaches 5 sigma (waveform.hpp), so a waveform is 0
/// between groups of pulses whose reaches leave a gap: such groups, at least the waveform's
/// least separation apart (and one bin), are sampled and detected apart, and a group of one
/// pulse is answered in closed form (a sampled Gaussian's fit is exact: its range, amplitude and
/// width; its energy is summed over its samples as detect_echoes does). What it leaves
/// out: the refit's subtraction of another group's fitted echo beyond that echo's 5 sigma reach.
/// Spans whose highest sample is below the threshold are not fitted (detect_echoes'
/// unfitted_below_w) and groups whose pulses' peaks add up to less than it are not sampled, nor
/// groups of pulses each below it whose waveform provably stays below it (pulses apart).
/// Appends to `out` in range order.
///
/// `reach_sigmas`: how far each contribution's pulse reaches, in its sigmas, when the pulses are
/// split into groups (the binned echo always reaches 5 sigma). kExactReachSigmas splits only
/// where the whole waveform is 0; less also splits pulses whose faint tails overlap, each group
/// detected without the other groups' tails (docs/weather.md, "Resolved particles").
inline constexpr double kExactReachSigmas = 5.0;
/// The reach of rain and snow surveys without fog (WeatherMedium::group_reach_sigmas): pulses
/// whose centres lie 4 sigma and the least separation (and a bin) apart are detected apart.
inline constexpr double kResolvedReachSigmas = 2.0;
void detect_echoes_in_groups(const WaveformConfig& config,
                             std::span<const EchoContribution> contributions,
                             const BinnedEcho& binned, double threshold_w, std::vector<Echo>& out,
                             double reach_sigmas = kExactReachSigmas);

}  // namespace beamtrace
