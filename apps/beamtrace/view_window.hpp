// The interactive window of `beamtrace view`: the CPU-rendered frames drawn with OpenGL in a GLFW
// window, keyboard and mouse navigation, the frame time in the title.
#pragma once

#include <string>
#include <vector>

#include "beamtrace/core/camera_pose.hpp"
#include "beamtrace/heightfield/view_progressive.hpp"
#include "beamtrace/heightfield/view_session.hpp"

namespace beamtrace::cli {

struct WindowOptions {
    /// PNG written from the window's framebuffer (glReadPixels) after the last frame; "" = none.
    std::string screenshot;
    /// Frames to run before closing (0: until the window is closed). The screenshot frame is
    /// drawn after every section the camera's window admits has loaded, so it equals the offline
    /// render of the same camera.
    int frames = 0;
    /// A scripted flight: one pose a frame (the camera moves), then the last pose stays (the
    /// camera is still and the frame refines); the keys and mouse take over after it.
    std::vector<CameraPose> path;
    /// CSV of every rendered frame, written on close ("" = none): frame, moving, step, width,
    /// height, render_ms, frame_ms.
    std::string frame_log;
    /// Coarser pixels while the camera moves, the full frame once it stops.
    ProgressiveConfig progressive;
    bool quiet = false;
};

/// Whether this binary was built with GLFW and OpenGL.
[[nodiscard]] bool view_window_available();
/// Throws ConfigError saying how to get the window when this binary has none.
void require_view_window();

/// Opens a window of the camera's size and runs the frame loop: sections load in the
/// background (ViewSession::update) and never stall a frame. Keys: W/S forward/back, A/D
/// sideways, Q/E (or Page Down/Up) down/up, arrows turn and tilt, Shift moves 4x faster, +/-
/// change the speed, Esc closes; dragging with the left mouse button turns the view. While the
/// camera moves, frames render with the pixel step of options.progressive; once it stops, the
/// full-resolution frame follows. Prints the frame-time summary (moving and still) on close
/// unless quiet. Throws
/// Error when no window can be opened (no display, or built without GLFW).
void run_view_window(ViewSession& session, ViewCamera camera, const RenderOptions& render,
                     const WindowOptions& options);

}  // namespace beamtrace::cli
