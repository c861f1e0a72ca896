#include "beamtrace/heightfield/view_progressive.hpp"

#include <algorithm>
#include <cmath>

namespace beamtrace {

std::vector<std::string> ProgressiveConfig::validate() const {
    std::vector<std::string> problems;
    if (!(moving_frame_s >= 0.0) || !std::isfinite(moving_frame_s)) {
        problems.push_back("view: --moving-frame-s " + std::to_string(moving_frame_s) +
                           ": not a time >= 0 (seconds; 0 = always full resolution)");
    }
    if (max_step < 1 || max_step > 8) {
        problems.push_back("view: --max-pixel-step " + std::to_string(max_step) +
                           ": not within 1 to 8");
    }
    return problems;
}

int ProgressiveScaler::step(bool moving, int width, int height) const {
    if (!moving || config_.moving_frame_s <= 0.0 || per_pixel_s_ <= 0.0) {
        return 1;
    }
    const double budget = config_.moving_frame_s - overhead_s_;
    for (int s = 1; s < config_.max_step; ++s) {
        const auto pixels =
            static_cast<double>((width + s - 1) / s) * static_cast<double>((height + s - 1) / s);
        if (pixels * per_pixel_s_ <= budget) {
            return s;
        }
    }
    return config_.max_step;
}

void ProgressiveScaler::record(std::size_t pixels, double render_s, double frame_s) {
    if (pixels == 0 || !(render_s > 0.0) || !std::isfinite(render_s) || !std::isfinite(frame_s)) {
        return;
    }
    const double now = render_s / static_cast<double>(pixels);
    const double outside = std::max(0.0, frame_s - render_s);
    const bool first = per_pixel_s_ <= 0.0;
    per_pixel_s_ = first ? now : 0.5 * (per_pixel_s_ + now);
    overhead_s_ = first ? outside : 0.5 * (overhead_s_ + outside);
}

ViewCamera stepped_camera(const ViewCamera& camera, int step) {
    ViewCamera c = camera;
    step = std::max(1, step);
    c.width = (camera.width + step - 1) / step;
    c.height = (camera.height + step - 1) / step;
    return c;
}

FrameTimeSummary summarize_frame_times(std::vector<double> ms) {
    FrameTimeSummary s;
    s.frames = ms.size();
    if (ms.empty()) {
        return s;
    }
    std::sort(ms.begin(), ms.end());
    const std::size_t n = ms.size();
    s.median_ms = n % 2 == 1 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
    // Nearest rank: the smallest value with at least 95 % of the values at or below it.
    const auto rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(n)));
    s.p95_ms = ms[std::max<std::size_t>(rank, 1) - 1];
    return s;
}

}  // namespace beamtrace
