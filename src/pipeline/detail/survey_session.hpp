// Everything a survey holds before its first block, and the stages one block goes through:
// shared by run_survey (one process, sinks on a writer thread) and run_survey_distributed (many
// ranks writing one LAS file). Not movable: the stages point into it.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "beamtrace/accel/backend.hpp"
#include "beamtrace/accel/moving_instances.hpp"
#include "beamtrace/io/point_sink.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/pipeline/survey.hpp"
#include "beamtrace/scene/scene.hpp"
#include "pipeline/detail/survey_block.hpp"
#include "pipeline/detail/survey_physics.hpp"
#include "pipeline/detail/survey_points.hpp"
#include "pipeline/detail/survey_rays.hpp"

namespace beamtrace::detail {

class SurveySession {
  public:
    /// Loads the scene, pattern and trajectory (ConfigError when they do not fit), builds the
    /// backend on `pool`, resolves the physics (the intensity reference range's pilot) and the
    /// sinks' facts (the footprint pilot). Writes nothing. Checks run.cancel between the steps.
    SurveySession(const SurveySpec& spec, const SurveyRunConfig& run, ThreadPool& pool);
    SurveySession(const SurveySession&) = delete;
    SurveySession& operator=(const SurveySession&) = delete;

    /// pulses, triangles, spheres, build_s and the intensity reference range so far.
    [[nodiscard]] const SurveyResult& result() const { return result_; }
    [[nodiscard]] const SinkFacts& facts() const { return facts_; }
    [[nodiscard]] std::uint64_t pulses() const { return result_.pulses; }
    /// Blocks of kBlockPulses pulses (the last one shorter).
    [[nodiscard]] std::size_t blocks() const;
    /// Block k (pulses [k kBlockPulses, ...)): poses and rays, trace, physics and points into
    /// w.points. Thread-safe; blocks in any order on any thread give the same points.
    void run_block(std::size_t k, BlockWork& w) const;
    /// The reasons of SurveyResult::few_points_reasons for a survey that gave `points` points.
    [[nodiscard]] std::vector<std::string> diagnose(std::uint64_t points, ThreadPool& pool) const;

  private:
    /// The moving parts' hits of block w's rays, each at its pulse's time (into w.hits).
    void trace_moving(BlockWork& w) const;

    const SurveySpec* spec_;
    Scene scene_;
    std::unique_ptr<ScanPattern> pattern_;
    std::unique_ptr<Trajectory> trajectory_;
    std::unique_ptr<Backend> backend_;
    /// The scene's moving parts, traced at each pulse's time (none: a still scene).
    std::optional<MovingInstances> moving_;
    std::optional<PulseSimulator> sim_;
    std::optional<SurveyPhysics> physics_;
    SurveyRaySource source_;
    SurveyPoints points_;
    SinkFacts facts_;
    SurveyResult result_;
    std::size_t sub_rays_ = 1, max_returns_ = 1;
};

}  // namespace beamtrace::detail
