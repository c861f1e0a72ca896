// The survey's points stage: each pulse's returns (or, without physics, its one hit) become
// points in world coordinates, labelled with the scene part that was hit.
#pragma once

#include "beamtrace/scene/scene.hpp"
#include "pipeline/detail/survey_block.hpp"

namespace beamtrace::detail {

struct SurveyPoints {
    const Scene* scene = nullptr;
    bool physics = false;  ///< points from w.returns (else one per hit ray)
    std::size_t sub_rays = 1;
    std::size_t max_returns = 1;

    /// Appends the block's points to w.points.points, in pulse order. Thread-safe.
    void run(BlockWork& w) const;
};

}  // namespace beamtrace::detail
