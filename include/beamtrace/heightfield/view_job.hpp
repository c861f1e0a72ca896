// `beamtrace view` as settings: the height field, session, camera and render options the CLI
// binds its options to (declared once in the library, with their defaults), the text forms of
// the view's sizes, and the checks of how the modes combine (docs/view.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "beamtrace/core/camera_pose.hpp"
#include "beamtrace/core/cancel.hpp"
#include "beamtrace/heightfield/view_camera.hpp"
#include "beamtrace/heightfield/view_progressive.hpp"
#include "beamtrace/heightfield/view_renderer.hpp"
#include "beamtrace/heightfield/view_session.hpp"

namespace beamtrace {

struct ViewJobConfig {
    std::vector<std::filesystem::path> inputs;  ///< LAS files or folders of .las files
    ViewSessionConfig session;                  ///< height field, memory budget, threads
    ViewCamera camera;                 ///< field of view and image size (the pose comes from below)
    RenderOptions render;              ///< shading, fog, sky
    std::optional<CameraPose> pose;    ///< one view from here (docs/camera.md)
    std::filesystem::path path;        ///< or a fly-through: camera path CSV, one frame per row
    std::filesystem::path output;      ///< PNG (pose) or folder of frame_NNNNN.png (path)
    bool interactive = false;          ///< a window instead; starts at `pose` when given
    std::filesystem::path screenshot;  ///< interactive: write the last frame here and close
    int frames = 0;                    ///< interactive: close after this many (0: never)
    std::filesystem::path mp4;         ///< path: also encode the frames into this MP4
    double fps = 25.0;                 ///< frame rate of the MP4
    bool prefetch = true;  ///< path: load the next frame's sections while this one renders
    /// interactive: one CSV line per frame (index, moving, pixel step, size, render and frame
    /// time) written here on close; "" = none.
    std::filesystem::path frame_log;
    /// interactive: coarser pixels while the camera moves, the full frame once it stops.
    ProgressiveConfig progressive;
    /// Checked before each frame loads, renders and is written: once requested,
    /// run_view_frames removes the frames it wrote and the MP4's temporary file and throws
    /// Interrupted. Null: runs to the end. The token must outlive the call.
    const CancelToken* cancel = nullptr;

    /// Every problem with how the modes combine, in the order the CLI reports them; empty
    /// when valid (the camera and height field are checked by their own validate()).
    [[nodiscard]] std::vector<std::string> validate() const;
    /// The poses to render: `pose`, or the camera path's (read from the file; InputError);
    /// empty without either (run_view_frames: the overview; interactive: starts there). An
    /// interactive window flies a path's poses one a frame, then stays at the last.
    [[nodiscard]] std::vector<CameraPose> poses() const;
};

/// One frame of run_view_frames, as it is reported.
struct ViewFrame {
    std::size_t index = 0;
    IngestStats stats;                 ///< what was loaded for it (empty when nothing had to be)
    const ViewImage* image = nullptr;  ///< valid during the report only
    std::filesystem::path file;        ///< the PNG written
    double render_s = 0.0;             ///< rendering time of the frames so far
};

struct ViewFrameHooks {
    /// Section loading for frame `index`: points done of total (for a progress bar).
    std::function<void(std::size_t index, std::uint64_t done, std::uint64_t total)> loading;
    /// After frame `index` is written.
    std::function<void(const ViewFrame&)> written;
};

struct ViewFramesResult {
    std::size_t frames = 0;
    int prefetched = 0;     ///< sections loaded in the background while a frame rendered
    double render_s = 0.0;  ///< rendering time, all frames
    int mp4_frames = 0;     ///< frames in the MP4 (0: none written)
    std::string mp4_codec;  ///< the MP4's codec
};

/// Renders `poses` (job.pose: one PNG at job.output; job.path: frame_NNNNN.png into the folder
/// job.output, created, and the MP4 job.mp4 when given; no pose and no path: one PNG from
/// overview_camera() of all the data). Before frame i renders, frame i + 1's
/// sections start loading in the background (job.prefetch); every frame is the same as without.
/// Throws OutputError, ConfigError, and Interrupted (job.cancel; the frames written are removed,
/// and the folder if this call created it).
ViewFramesResult run_view_frames(const ViewJobConfig& job, ViewSession& session,
                                 const std::vector<CameraPose>& poses,
                                 const ViewFrameHooks& hooks = {});

/// "256MB", "1.5GiB", "1000000" (bytes): KB/MB/GB (or K/M/G) are powers of 1000, KiB/MiB/GiB
/// of 1024. Throws ConfigError naming the text.
[[nodiscard]] std::uint64_t parse_byte_size(std::string_view text);

/// The shortest of "NGB", "NMB", "NKB" or "N" (bytes) that is exactly `bytes`.
[[nodiscard]] std::string byte_size_text(std::uint64_t bytes);

/// "WxH" with positive integers into (w, h); throws ConfigError naming `what` and the text.
void parse_size_pair(std::string_view text, std::string_view what, int& w, int& h);

/// "NxN": the side of the square window of sections; throws ConfigError.
[[nodiscard]] int parse_section_window(std::string_view text);

}  // namespace beamtrace
