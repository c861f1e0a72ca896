// `beamtrace view`: ray-traced images of raw LAS files through out-of-core height-field sections.
// The options bind to the fields of ViewJobConfig (heightfield/view_job.hpp), which holds the
// defaults (those of HeightFieldConfig, ViewCamera and RenderOptions).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/heightfield/data_framing.hpp"
#include "beamtrace/heightfield/view_job.hpp"
#include "beamtrace/io/mp4_writer.hpp"
#include "commands.hpp"
#include "interrupt.hpp"
#include "progress_bar.hpp"
#include "view_window.hpp"

namespace beamtrace::cli {
namespace {

struct ViewCommand {
    ViewJobConfig job;
    bool quiet = false;
    bool progress = false;
};

/// The points of the first load that are not in the image, and why. (Later loads fill only the
/// sections new to the window.)
void print_not_shown(const IngestStats& s, const ViewSession& session) {
    if (s.points_inserted >= s.points_read ||
        session.grid().loaded_sections() != s.sections_loaded) {
        return;
    }
    const std::string why = session.not_shown_reason();
    std::fprintf(stderr, "beamtrace: note: %llu of %llu points not shown: %s\n",
                 static_cast<unsigned long long>(s.points_read - s.points_inserted),
                 static_cast<unsigned long long>(s.points_read),
                 why.empty() ? "they lie outside every section" : why.c_str());
}

void print_stats(const IngestStats& s, const ViewSession& session, bool quiet) {
    for (const auto& w : s.warnings) {
        std::fprintf(stderr, "beamtrace: warning: %s\n", w.c_str());
    }
    print_not_shown(s, session);
    if (quiet || s.points_read == 0) {
        return;
    }
    std::printf(
        "loaded %d sections of %g-unit cells: %llu of %llu points in %.3f s (%.1f M "
        "points/s); %.1f MB resident\n",
        session.grid().loaded_sections(), session.grid().config().cell_size,
        static_cast<unsigned long long>(s.points_inserted),
        static_cast<unsigned long long>(s.points_read), s.seconds,
        s.seconds > 0 ? static_cast<double>(s.points_read) / s.seconds / 1e6 : 0.0,
        static_cast<double>(session.budgeted_bytes()) / 1e6);
}

/// The mode checks, and the window and ffmpeg where asked for: before any file is read.
void check_modes(const ViewJobConfig& job) {
    if (const auto problems = job.validate(); !problems.empty()) {
        std::string msg = problems.front();
        for (std::size_t i = 1; i < problems.size(); ++i) {
            msg += "; " + problems[i];
        }
        throw ConfigError(msg);
    }
    if (job.interactive) {
        require_view_window();
    }
    if (!job.mp4.empty() && !find_ffmpeg()) {
        throw ConfigError("view: --mp4 " + job.mp4.string() +
                          " needs ffmpeg on PATH (apt install ffmpeg); the PNG frames do not");
    }
}

/// Every camera, before the LAS files are read.
void check_cameras(const ViewJobConfig& job, const std::vector<CameraPose>& poses) {
    for (const auto& p : poses) {
        ViewCamera c = job.camera;
        c.set_pose(p);
        c.validate();
    }
}

void run_interactive(const ViewCommand& c, ViewSession& session,
                     const std::vector<CameraPose>& poses) {
    ViewCamera camera = c.job.camera;
    WindowOptions window;
    if (!c.job.path.empty()) {
        window.path = poses;  // flown one pose a frame
    }
    if (poses.empty()) {
        const PointsBox box = points_box(session.sources());
        camera = overview_camera(box.lo, box.hi, camera);
    } else {
        camera.set_pose(poses.front());
    }
    window.screenshot = c.job.screenshot.string();
    window.frames = c.job.frames;
    window.frame_log = c.job.frame_log.string();
    window.progressive = c.job.progressive;
    window.quiet = c.quiet;
    run_view_window(session, camera, c.job.render, window);
}

/// The frames of --camera (one) or --path (one per pose): a progress bar while each frame's
/// sections load, and the summary.
void run_frames(const ViewCommand& c, ViewSession& session, const std::vector<CameraPose>& poses) {
    const bool show = !c.quiet && (c.progress || stderr_is_terminal());
    std::unique_ptr<ProgressBar> bar;
    ViewFrameHooks hooks;
    hooks.loading = [&](std::size_t, std::uint64_t done, std::uint64_t total) {
        if (!bar) {
            bar = std::make_unique<ProgressBar>("loading sections", show);
        }
        bar->update(static_cast<std::size_t>(done), static_cast<std::size_t>(total));
    };
    hooks.written = [&](const ViewFrame& f) {
        if (bar) {
            bar->finish();
            bar.reset();
        }
        print_stats(f.stats, session, c.quiet);
        if (!c.quiet && c.job.path.empty()) {
            std::printf("rendered %dx%d in %.1f ms (%zu of %zu pixels hit)\nwrote %s\n",
                        f.image->width, f.image->height, f.render_s * 1e3, f.image->hits(),
                        f.image->depth.size(), f.file.string().c_str());
        }
    };
    ViewJobConfig job = c.job;
    job.cancel = &interrupt_token();
    catch_interrupts();
    const ViewFramesResult r = run_view_frames(job, session, poses, hooks);
    if (c.quiet) {
        return;
    }
    if (r.mp4_frames > 0) {
        std::printf("wrote %s (%d frames, %s, %g frames/s)\n", c.job.mp4.string().c_str(),
                    r.mp4_frames, r.mp4_codec.c_str(), c.job.fps);
    }
    if (!c.job.path.empty()) {
        std::printf(
            "rendered %zu frames of %dx%d, %.1f ms per frame; %d sections loaded in the "
            "background; peak %.1f MB of the budget; wrote %s/frame_*.png\n",
            r.frames, c.job.camera.width, c.job.camera.height,
            r.render_s * 1e3 / static_cast<double>(r.frames), r.prefetched,
            static_cast<double>(session.peak_budgeted_bytes()) / 1e6,
            c.job.output.string().c_str());
    }
}

int run(const ViewCommand& c) {
    check_modes(c.job);
    const std::vector<CameraPose> poses = c.job.poses();
    check_cameras(c.job, poses);
    ViewSession session(c.job.inputs, c.job.session);
    for (const auto& w : session.sources().warnings()) {
        std::fprintf(stderr, "beamtrace: warning: %s\n", w.c_str());
    }
    if (c.job.interactive) {
        run_interactive(c, session, poses);
    } else {
        run_frames(c, session, poses);
    }
    return 0;
}

/// --camera, --path, --output, --fov, --size: the job's poses and job.camera.
void add_camera_options(CLI::App* cmd, ViewJobConfig& job) {
    cmd->add_option_function<std::string>(
        "--camera",
        [&job](const std::string& s) { job.pose = parse_camera_pose(s, "--camera").pose; },
        "x,y,z,yaw,pitch: position in the files' units, yaw and pitch in degrees "
        "(docs/camera.md: yaw 0 looks along +x, yaw > 0 pans right, i.e. clockwise seen from "
        "above; pitch > 0 tilts up, -90 = straight down)");
    cmd->add_option("--path", job.path,
                    "Camera path CSV (header x,y,z,yaw,pitch): one frame per row into --output/");
    cmd->add_option("--output", job.output, "PNG file (--camera) or directory (--path)");
    cmd->add_option("--fov", job.camera.hfov_deg, "Horizontal field of view in degrees")
        ->capture_default_str();
    cmd->add_option_function<std::string>(
           "--size",
           [&job](const std::string& s) {
               parse_size_pair(s, "--size", job.camera.width, job.camera.height);
           },
           "Image size WxH")
        ->default_str(std::to_string(job.camera.width) + "x" + std::to_string(job.camera.height));
}

/// The height field, its memory budget and the threads: job.session.
void add_field_options(CLI::App* cmd, ViewSessionConfig& session) {
    HeightFieldConfig& f = session.field;
    cmd->add_option("--cell-size", f.cell_size,
                    "Finest cell edge in the files' units (0 = from the point density: 1.5 x "
                    "the mean point spacing of the headers' footprints, rounded up to 1-2-5)")
        ->capture_default_str();
    cmd->add_option("--levels", f.levels, "Quadtree levels per section")->capture_default_str();
    cmd->add_option("--section-cells", f.section_cells,
                    "Cells per side of a section's coarsest level (power of two)")
        ->capture_default_str();
    cmd->add_option_function<std::string>(
           "--sections", [&f](const std::string& s) { f.sections = parse_section_window(s); },
           "Window of NxN sections around the camera")
        ->default_str(std::to_string(f.sections) + "x" + std::to_string(f.sections));
    cmd->add_option_function<std::string>(
           "--memory-budget",
           [&f](const std::string& s) { f.memory_budget_bytes = parse_byte_size(s); },
           "Bytes for resident sections and read buffers (e.g. 256MB, 2GiB)")
        ->default_str(byte_size_text(f.memory_budget_bytes));
    cmd->add_option_function<std::string>(
           "--color", [&f](const std::string& s) { f.color = parse_color_mode(s); },
           "height | rgb | intensity | classification")
        ->default_str(std::string(color_mode_name(f.color)));
    cmd->add_option("--height-stacks", f.height_stacks,
                    "Up to K occupied height intervals per cell (2-8), so rays pass under "
                    "bridges, wires and tree crowns (0 = one column per cell)")
        ->capture_default_str();
    cmd->add_option("--stack-gap", f.stack_gap,
                    "--height-stacks: vertical gap that separates intervals, in the files' units "
                    "(0 = 3 cells)")
        ->capture_default_str();
    cmd->add_option("--fill-gaps", f.gap_fill_cells,
                    "Close runs of up to N empty cells between occupied ones (rows, then "
                    "columns) at the lower height, so scan lines read as a surface (0 = off)")
        ->capture_default_str();
    cmd->add_option("--threads", session.threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
}

/// The window: --interactive and its options.
void add_window_options(CLI::App* cmd, ViewJobConfig& job) {
    cmd->add_flag("--interactive", job.interactive,
                  "Open a window (GLFW/OpenGL): WASD/arrows/Q/E and mouse drag to fly, frame time "
                  "in the title; starts at --camera when given, or flies --path (a pose a frame)");
    cmd->add_option("--screenshot", job.screenshot,
                    "--interactive: write the window's last frame (read back from OpenGL) to "
                    "this PNG and close");
    cmd->add_option("--frames", job.frames,
                    "--interactive: close after this many frames (0 = when the window is closed)");
    cmd->add_option("--frame-log", job.frame_log,
                    "--interactive: write one CSV line per frame here on close (frame, moving, "
                    "step, width, height, render_ms, frame_ms)");
    cmd->add_option("--moving-frame-s", job.progressive.moving_frame_s,
                    "--interactive: frame time aimed at while the camera moves, in seconds "
                    "(coarser pixels; the full frame once it stops); 0 = always full resolution")
        ->capture_default_str();
    cmd->add_option("--max-pixel-step", job.progressive.max_step,
                    "--interactive: coarsest pixel step while moving (1-8)")
        ->capture_default_str();
}

/// Fog, shading, the fly-through's video and prefetching, the window, the output.
void add_mode_options(CLI::App* cmd, ViewCommand& c) {
    ViewJobConfig& job = c.job;
    cmd->add_option("--eye-dome", job.render.eye_dome,
                    "Eye-dome lighting strength: outlines depth edges (columns, crowns, walls); "
                    "0 = off, 1 = clear")
        ->capture_default_str();
    cmd->add_option("--fog", job.render.fog_distance, "Fog distance in the files' units (0 = none)")
        ->capture_default_str();
    cmd->add_flag_callback(
        "--no-shading", [&job] { job.render.shading = false; }, "Flat colours, no normal shading");
    cmd->add_flag_callback(
        "--no-prefetch", [&job] { job.prefetch = false; },
        "--path: load each frame's sections only when it is due (no background loading while "
        "the previous frame renders)");
    cmd->add_option("--mp4", job.mp4,
                    "--path: also encode the frames into this MP4 (needs ffmpeg on PATH)");
    cmd->add_option("--fps", job.fps, "Frame rate of the --mp4 video")->capture_default_str();
    cmd->add_flag("--quiet", c.quiet, "No progress bar and no summary");
    cmd->add_flag("--progress", c.progress, "Show the progress bar even when not on a terminal");
}

}  // namespace

std::function<int()> add_view_command(CLI::App& app) {
    auto c = std::make_shared<ViewCommand>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Ray-trace views of raw LAS files through out-of-core height-field sections");
    cmd->add_option("files", c->job.inputs, "LAS files or directories of .las files")->required();
    add_camera_options(cmd, c->job);
    add_field_options(cmd, c->job.session);
    add_mode_options(cmd, *c);
    add_window_options(cmd, c->job);
    return [c] { return run(*c); };
}

}  // namespace beamtrace::cli
