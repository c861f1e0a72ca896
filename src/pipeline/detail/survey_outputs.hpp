// A survey's outputs: the header facts of its sinks and the sinks the survey file asks for,
// chosen from the registry (io/point_sink_registry.hpp).
#pragma once

#include <cstdint>
#include <optional>

#include "beamtrace/io/point_sink.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/scene/scene.hpp"
#include "pipeline/detail/sink_set.hpp"

namespace beamtrace::detail {

/// The platform over the survey window in world coordinates, at output.trajectory_rate_hz;
/// nullopt when the rate is 0 or there are no pulses.
[[nodiscard]] std::optional<SampledTrajectory> survey_trajectory_samples(
    const SurveySpec& spec, const ScanPattern& pattern, const Trajectory& trajectory,
    const Vec3d& origin_m, std::uint64_t pulses);

/// What the survey's sinks are told before the first point. `sim` is null without physics.
[[nodiscard]] SinkFacts survey_sink_facts(const SurveySpec& spec, const SurveyRunConfig& run,
                                          const Scene& scene, const ScanPattern& pattern,
                                          const Trajectory& trajectory, const PulseSimulator* sim,
                                          std::uint64_t pulses);

/// Opens, in registry order, every sink that applies to `facts` and is not switchable or is
/// switched on in spec.outputs.
[[nodiscard]] SinkSet open_survey_sinks(const SurveySpec& spec, const SinkFacts& facts);
/// The sinks of a run: open_survey_sinks when run.write_files, then run.extra_sinks in order.
[[nodiscard]] SinkSet open_run_sinks(const SurveySpec& spec, const SurveyRunConfig& run,
                                     const SinkFacts& facts);

}  // namespace beamtrace::detail
