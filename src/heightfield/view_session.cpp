#include "beamtrace/heightfield/view_session.hpp"

#include <cmath>

namespace beamtrace {

ViewSession::ViewSession(std::span<const std::filesystem::path> inputs,
                         const ViewSessionConfig& config)
    : config_(config), sources_(inputs), pool_(config.threads) {
    config_.field.validate();
    grid_ = std::make_unique<SectionGrid>(config_.field, sources_.min());
}

IngestStats ViewSession::move_to(const Vec3d& camera_position, const IngestProgress& progress) {
    const std::vector<int> fresh = grid_->recenter(camera_position.x, camera_position.y,
                                                   sources_.bounds(), config_.ingest.block_bytes);
    return ingest_sections(sources_, *grid_, fresh, pool_, config_.ingest, progress);
}

}  // namespace beamtrace
