// The survey's physics stage: each pulse's sub-ray hits become its returns (and, when kept,
// its sampled waveform), with the scene's materials.
#pragma once

#include <cstdint>
#include <vector>

#include "beamtrace/physics/material.hpp"
#include "beamtrace/physics/pulse.hpp"
#include "beamtrace/scene/scene.hpp"
#include "pipeline/detail/survey_block.hpp"

namespace beamtrace::detail {

class SurveyPhysics {
  public:
    /// `sim` and `scene` must outlive the stage; `materials` are the scene's (survey_materials).
    SurveyPhysics(const PulseSimulator& sim, const Scene& scene, std::vector<Material> materials,
                  std::uint64_t seed);

    [[nodiscard]] std::size_t sub_rays() const { return sim_->sub_ray_count(); }
    [[nodiscard]] std::size_t max_returns() const {
        return static_cast<std::size_t>(sim_->config().max_returns);
    }
    [[nodiscard]] bool keeps_waveforms() const { return sim_->config().keep_waveform; }

    /// Fills w.returns and w.return_count from w.rays and w.hits; appends the waveforms to
    /// w.points when they are kept. Thread-safe (const): blocks run on many threads at once.
    void run(BlockWork& w) const;

  private:
    void keep_waveform(BlockWork& w, std::size_t k) const;

    const PulseSimulator* sim_;
    const Scene* scene_;
    std::vector<Material> materials_;
    std::uint64_t seed_;
};

}  // namespace beamtrace::detail
