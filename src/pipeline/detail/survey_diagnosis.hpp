// Why a survey gave no or very few points: a pilot of pulses spread over the survey is traced
// without range limits, and what it meets (nothing, the scene's box only, hits outside the
// range gate, hits the physics did not detect) is said in a line each.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/core/aabb.hpp"
#include "beamtrace/core/ray_batch.hpp"
#include "beamtrace/core/thread_pool.hpp"
#include "beamtrace/pipeline/survey.hpp"

namespace beamtrace::detail {

/// Fewer points than this fraction of the pulses is "very few" (a warning; none: an error
/// unless allowed).
inline constexpr double kFewPointsFraction = 1e-3;

/// Whether the ray from `o` along `d` meets the box `b` (slabs; touching counts).
[[nodiscard]] bool ray_meets_box(const Vec3d& o, const Vec3d& d, const Aabb& b);

/// `scan`'s version: when fewer than kFewPointsFraction of `rays` hit, why, a line each (how
/// many rays miss even the scene's box, and where the middle ray looks); else nothing.
[[nodiscard]] std::vector<std::string> diagnose_scan(const RayBatch& rays, std::size_t hits,
                                                     const Aabb& scene_bounds);

/// The reasons that `points` of `pulses` may have come out so few, or nothing when they are
/// not few. Traces the pilot of survey_reference_range.hpp with range limits [0, inf).
[[nodiscard]] std::vector<std::string> diagnose_survey(
    const SurveySpec& spec, const ScanPattern& pattern, const Trajectory& trajectory,
    const Backend& backend, const Aabb& scene_bounds, std::uint64_t pulses, std::uint64_t points,
    ThreadPool& pool);

}  // namespace beamtrace::detail
