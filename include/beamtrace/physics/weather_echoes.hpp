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
/// width; its energy, the contribution's, within the 5 sigma truncation's 6e-7). What it leaves
/// out: the refit's subtraction of another group's fitted echo, at least 10 sigma away (below
/// exp(-50) = 2e-22 of that echo's amplitude). Appends to `out` in range order.
void detect_echoes_in_groups(const WaveformConfig& config,
                             std::span<const EchoContribution> contributions,
                             const BinnedEcho& binned, double threshold_w, std::vector<Echo>& out);

}  // namespace beamtrace
