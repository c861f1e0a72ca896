// Progressive refinement of interactive views: while the camera moves, frames are rendered with
// fewer, larger pixels, as coarse as it takes to keep the frame time aimed at; once it stops,
// the full-resolution frame (the same image as render_view and its reference) follows.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "beamtrace/heightfield/view_camera.hpp"

namespace beamtrace {

struct ProgressiveConfig {
    /// Frame time aimed at while the camera moves [s]: the pixel step is the smallest whose
    /// frame is predicted (from the last frames' render time per pixel and their time outside
    /// the render: input, drawing, presenting) to take at most this; 0 = every frame at full
    /// resolution.
    double moving_frame_s = 0.033;
    /// The coarsest pixel step (each rendered pixel then covers max_step x max_step pixels of
    /// the window), 1 to 8.
    int max_step = 4;

    /// Every problem, "view: --moving-frame-s ...: what" (empty when valid).
    [[nodiscard]] std::vector<std::string> validate() const;
};

/// Chooses the pixel step of each interactive frame from the render times of the last ones.
class ProgressiveScaler {
  public:
    explicit ProgressiveScaler(const ProgressiveConfig& config) : config_(config) {}

    /// 1 when the camera is still (or refinement is off); while it moves, the smallest step
    /// whose frame fits in moving_frame_s by the current estimates (the time outside the render
    /// plus the pixels times the time per pixel; 1 before any estimate, max_step when not even
    /// that fits).
    [[nodiscard]] int step(bool moving, int width, int height) const;

    /// A frame of `pixels` rendered pixels took `render_s` to render and `frame_s` in all
    /// (render, drawing, presenting; frame_s < render_s counts as render_s): updates the time
    /// per pixel and the time outside the render, each the mean of this frame's and the
    /// previous estimate, so that one slow frame does not swing them.
    void record(std::size_t pixels, double render_s, double frame_s);

    [[nodiscard]] double seconds_per_pixel() const { return per_pixel_s_; }
    [[nodiscard]] double overhead_seconds() const { return overhead_s_; }

  private:
    ProgressiveConfig config_;
    double per_pixel_s_ = 0.0;  ///< 0: no estimate yet
    double overhead_s_ = 0.0;
};

/// The camera of a frame rendered with pixel step `step`: the same pose and field of view,
/// ceil(width / step) x ceil(height / step) pixels (drawn stretched over the window).
[[nodiscard]] ViewCamera stepped_camera(const ViewCamera& camera, int step);

/// Frame times of an interactive view, split by whether the camera moved.
struct FrameTimeSummary {
    std::size_t frames = 0;
    double median_ms = 0.0;
    double p95_ms = 0.0;  ///< the 95th percentile (nearest rank)
    [[nodiscard]] double fps() const { return median_ms > 0 ? 1e3 / median_ms : 0.0; }
};

/// Median and 95th percentile (nearest rank) of `ms`; all zero when empty.
[[nodiscard]] FrameTimeSummary summarize_frame_times(std::vector<double> ms);

}  // namespace beamtrace
