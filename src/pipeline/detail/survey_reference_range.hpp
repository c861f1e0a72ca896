// The survey's intensity reference range (physics.intensity.reference_range_m: auto): a pilot
// of pulses spread evenly over the survey, traced as ideal single rays before the run, gives
// the survey's nominal range; R_ref is half of it (docs/physics.md "LAS intensity").
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/pipeline/survey.hpp"

namespace beamtrace::detail {

/// Pulses of the pilot (all of them when the survey has fewer).
inline constexpr std::size_t kPilotPulses = 1024;
/// R_ref = this times the nominal range: a white Lambertian facing the sensor at the nominal
/// range reads 65535 / 4 (two bits of headroom for nearer, brighter or specular targets).
inline constexpr double kReferenceRangeFraction = 0.5;

/// The pilot's rays: pulses floor((2k + 1) P / (2 K)), k < K = min(max_pulses, P), of the P
/// pulses of `pattern`, each along its beam axis from the platform's pose (no noise, no
/// sub-rays), with the survey's range limits.
[[nodiscard]] RayBatch pilot_rays(const SurveySpec& spec, const ScanPattern& pattern,
                                  const Trajectory& trajectory,
                                  std::size_t max_pulses = kPilotPulses);

/// The box of the pilot's first hits (scene coordinates), grown by a tenth of its size on every
/// side; nullopt when none hits. Where a survey's points will be, for preview.png.
[[nodiscard]] std::optional<Aabb> pilot_hit_bounds(const SurveySpec& spec,
                                                   const ScanPattern& pattern,
                                                   const Trajectory& trajectory,
                                                   const Backend& backend, ThreadPool& pool);

/// The median first-hit range of the pilot: pulses floor((2k + 1) P / (2 K)), k < K =
/// min(kPilotPulses, P), of the P pulses of `pattern`, each traced along its beam axis from the
/// platform's pose (no noise, no sub-rays) with `backend`; nullopt when none hits. Deterministic.
[[nodiscard]] std::optional<double> survey_nominal_range_m(const SurveySpec& spec,
                                                           const ScanPattern& pattern,
                                                           const Trajectory& trajectory,
                                                           const Backend& backend,
                                                           ThreadPool& pool);

/// What the survey reports of its intensity scale.
struct ReferenceRange {
    double reference_range_m = kDefaultIntensityReferenceRange_m;  ///< R_ref in use
    bool automatic = false;                 ///< from the pilot (else the survey file's number)
    std::optional<double> nominal_range_m;  ///< the pilot's median (automatic only)
};

/// Sets physics.radiometry.intensity_reference_range_m when it is unset (auto): to
/// kReferenceRangeFraction times the nominal range, or kDefaultIntensityReferenceRange_m when
/// the pilot hits nothing. Returns what was used.
ReferenceRange resolve_reference_range(PhysicsConfig& physics, const SurveySpec& spec,
                                       const ScanPattern& pattern, const Trajectory& trajectory,
                                       const Backend& backend, ThreadPool& pool);

}  // namespace beamtrace::detail
