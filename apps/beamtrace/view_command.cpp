// `beamtrace view`: ray-traced images of raw LAS files through out-of-core height-field sections.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "beamtrace/heightfield/camera_path.hpp"
#include "beamtrace/heightfield/view_session.hpp"
#include "beamtrace/io/mp4_writer.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "commands.hpp"
#include "progress_bar.hpp"
#include "view_window.hpp"

namespace beamtrace::cli {
namespace {

struct ViewOptions {
    std::vector<std::string> files;
    std::string camera;
    std::string path;
    std::string output;
    double fov_deg = 60.0;
    std::string size = "1920x1080";
    double cell_size = 1.0;
    int levels = 8;
    int section_cells = 32;
    std::string sections = "4x4";
    std::string memory_budget = "1GB";
    std::string color = "height";
    double fog = 0.0;
    bool no_shading = false;
    unsigned threads = 0;
    bool quiet = false;
    bool progress = false;
    bool no_prefetch = false;
    bool interactive = false;
    std::string screenshot;
    int frames = 0;
    std::string mp4;
    double fps = 25.0;
    int height_stacks = 0;
    double stack_gap = 0.0;
};

/// "WxH" with positive integers.
void parse_pair(const std::string& text, const std::string& what, int& a, int& b) {
    const auto x = text.find('x');
    try {
        std::size_t n1 = 0, n2 = 0;
        if (x == std::string::npos) {
            throw std::invalid_argument("no x");
        }
        a = std::stoi(text.substr(0, x), &n1);
        b = std::stoi(text.substr(x + 1), &n2);
        if (n1 != x || n2 != text.size() - x - 1 || a < 1 || b < 1) {
            throw std::invalid_argument("bad");
        }
    } catch (const std::exception&) {
        throw ConfigError(what + " '" + text + "' is not of the form WxH with positive integers");
    }
}

/// "256MB", "1.5GiB", "1000000" (bytes). KB/MB/GB are powers of 1000, KiB/MiB/GiB of 1024.
std::uint64_t parse_bytes(const std::string& text) {
    std::size_t used = 0;
    double value = 0;
    try {
        value = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    std::string unit = text.substr(used);
    for (auto& c : unit) {
        c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    double factor = 0;
    if (unit.empty() || unit == "B") {
        factor = 1;
    } else if (unit == "KB" || unit == "K") {
        factor = 1e3;
    } else if (unit == "MB" || unit == "M") {
        factor = 1e6;
    } else if (unit == "GB" || unit == "G") {
        factor = 1e9;
    } else if (unit == "KIB") {
        factor = 1024.0;
    } else if (unit == "MIB") {
        factor = 1024.0 * 1024.0;
    } else if (unit == "GIB") {
        factor = 1024.0 * 1024.0 * 1024.0;
    }
    if (used == 0 || factor == 0 || !(value > 0) || !std::isfinite(value * factor)) {
        throw ConfigError("memory budget '" + text +
                          "' is not a size such as 256MB, 2GB or 512MiB");
    }
    return static_cast<std::uint64_t>(value * factor);
}

void print_stats(const IngestStats& s, const ViewSession& session, bool quiet) {
    for (const auto& w : s.warnings) {
        std::fprintf(stderr, "beamtrace: warning: %s\n", w.c_str());
    }
    if (quiet || s.points_read == 0) {
        return;
    }
    std::printf(
        "loaded %d sections: %llu of %llu points in %.3f s (%.1f M points/s); %.1f MB "
        "resident\n",
        session.grid().loaded_sections(), static_cast<unsigned long long>(s.points_inserted),
        static_cast<unsigned long long>(s.points_read), s.seconds,
        s.seconds > 0 ? static_cast<double>(s.points_read) / s.seconds / 1e6 : 0.0,
        static_cast<double>(session.budgeted_bytes()) / 1e6);
}

int run(const ViewOptions& o) {
    if (o.interactive) {
        if (!o.path.empty()) {
            throw ConfigError("view: --interactive starts at --camera (optional), not --path");
        }
        require_view_window();  // before reading any file
    } else {
        if (o.camera.empty() == o.path.empty()) {
            throw ConfigError(
                "view: give exactly one of --camera x,y,z,yaw,pitch and --path FILE.csv (or "
                "--interactive)");
        }
        if (o.output.empty()) {
            throw ConfigError(
                "view: --output is required (a PNG file with --camera, a folder "
                "with --path)");
        }
        if (!o.screenshot.empty() || o.frames != 0) {
            throw ConfigError("view: --screenshot and --frames go with --interactive");
        }
    }
    if (!o.mp4.empty()) {
        if (o.path.empty()) {
            throw ConfigError("view: --mp4 goes with --path (a fly-through)");
        }
        if (!(o.fps > 0) || !std::isfinite(o.fps)) {
            throw ConfigError("view: --fps " + std::to_string(o.fps) + " is not positive");
        }
        if (!find_ffmpeg()) {
            throw ConfigError("view: --mp4 " + o.mp4 +
                              " needs ffmpeg on PATH (apt install ffmpeg); the PNG frames do not");
        }
    }
    if (o.frames < 0) {
        throw ConfigError("view: --frames " + std::to_string(o.frames) + " is negative");
    }
    ViewSessionConfig config;
    config.field.cell_size = o.cell_size;
    config.field.levels = o.levels;
    config.field.section_cells = o.section_cells;
    int sx = 0, sy = 0;
    parse_pair(o.sections, "--sections", sx, sy);
    if (sx != sy) {
        throw ConfigError("--sections '" + o.sections + "' must be square (NxN)");
    }
    config.field.sections = sx;
    config.field.memory_budget_bytes = parse_bytes(o.memory_budget);
    config.field.color = parse_color_mode(o.color);
    config.field.height_stacks = o.height_stacks;
    config.field.stack_gap = o.stack_gap;
    config.threads = o.threads;
    ViewCamera camera;
    camera.hfov_deg = o.fov_deg;
    parse_pair(o.size, "--size", camera.width, camera.height);
    RenderOptions render;
    render.shading = !o.no_shading;
    render.fog_distance = o.fog;

    std::vector<CameraPose> poses;
    if (o.interactive && o.camera.empty()) {
        // Decided once the files' bounds are known (below).
    } else if (!o.camera.empty()) {
        poses.push_back(parse_camera_pose(o.camera, "--camera"));
    } else {
        poses = read_camera_path(o.path);
    }
    // Check every camera before loading anything.
    for (const auto& p : poses) {
        ViewCamera c = camera;
        c.position = p.position;
        c.yaw_deg = p.yaw_deg;
        c.pitch_deg = p.pitch_deg;
        c.validate();
    }
    const std::vector<std::filesystem::path> inputs(o.files.begin(), o.files.end());
    ViewSession session(inputs, config);
    for (const auto& w : session.sources().warnings()) {
        std::fprintf(stderr, "beamtrace: warning: %s\n", w.c_str());
    }
    if (o.interactive) {
        if (poses.empty()) {
            // Above the middle of the data, a tenth of its extent over its highest point,
            // looking 30 degrees down along +x.
            const Vec3d lo = session.sources().min(), hi = session.sources().max();
            const double extent = std::max(hi.x - lo.x, hi.y - lo.y);
            camera.position = {0.5 * (lo.x + hi.x) - 0.3 * (hi.x - lo.x), 0.5 * (lo.y + hi.y),
                               hi.z + 0.1 * extent};
            camera.yaw_deg = 0.0;
            camera.pitch_deg = -30.0;
        } else {
            camera.position = poses[0].position;
            camera.yaw_deg = poses[0].yaw_deg;
            camera.pitch_deg = poses[0].pitch_deg;
        }
        WindowOptions window;
        window.screenshot = o.screenshot;
        window.frames = o.frames;
        window.quiet = o.quiet;
        run_view_window(session, camera, render, window);
        return 0;
    }
    if (!o.path.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(o.output, ec);
        if (ec) {
            throw OutputError(o.output + ": cannot create directory: " + ec.message());
        }
    }
    const bool show = !o.quiet && (o.progress || stderr_is_terminal());
    double render_s = 0;
    ViewImage image;  // its buffers are reused frame after frame
    int prefetched = 0;
    std::unique_ptr<Mp4Writer> video;
    if (!o.mp4.empty()) {
        video = std::make_unique<Mp4Writer>(o.mp4, camera.width, camera.height, o.fps);
    }
    for (std::size_t i = 0; i < poses.size(); ++i) {
        camera.position = poses[i].position;
        camera.yaw_deg = poses[i].yaw_deg;
        camera.pitch_deg = poses[i].pitch_deg;
        ProgressBar bar("loading sections", show);
        // Waits for the sections prefetched while the previous frame rendered, then loads
        // whatever did not fit next to them: frame i is the same as without prefetching.
        const IngestStats stats =
            session.move_to(camera.position, [&](std::uint64_t done, std::uint64_t total) {
                bar.update(static_cast<std::size_t>(done), static_cast<std::size_t>(total));
            });
        bar.finish();
        print_stats(stats, session, o.quiet);
        prefetched += stats.sections_prefetched;
        if (i + 1 < poses.size() && !o.no_prefetch) {
            session.prefetch(poses[i + 1].position);  // loads on the loader thread meanwhile
        }
        const auto start = std::chrono::steady_clock::now();
        session.render(camera, render, image);
        render_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::filesystem::path out = o.output;
        if (!o.path.empty()) {
            char name[32];
            std::snprintf(name, sizeof name, "frame_%05zu.png", i);
            out /= name;
        }
        write_png_rgb8(out, image.width, image.height, image.rgb);
        if (video) {
            video->write(image.rgb);
        }
        if (!o.quiet && o.path.empty()) {
            std::printf("rendered %dx%d in %.1f ms (%zu of %zu pixels hit)\nwrote %s\n",
                        image.width, image.height, render_s * 1e3, image.hits(), image.depth.size(),
                        out.string().c_str());
        }
    }
    if (video) {
        video->commit();
        if (!o.quiet) {
            std::printf("wrote %s (%d frames, %s, %g frames/s)\n", o.mp4.c_str(), video->frames(),
                        video->codec().c_str(), o.fps);
        }
    }
    if (!o.quiet && !o.path.empty()) {
        std::printf(
            "rendered %zu frames of %dx%d, %.1f ms per frame; %d sections loaded in the "
            "background; peak %.1f MB of the budget; wrote %s/frame_*.png\n",
            poses.size(), camera.width, camera.height,
            render_s * 1e3 / static_cast<double>(poses.size()), prefetched,
            static_cast<double>(session.peak_budgeted_bytes()) / 1e6, o.output.c_str());
    }
    return 0;
}

}  // namespace

std::function<int()> add_view_command(CLI::App& app) {
    auto opts = std::make_shared<ViewOptions>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Ray-trace views of raw LAS files through out-of-core height-field sections");
    cmd->add_option("files", opts->files, "LAS files or directories of .las files")->required();
    cmd->add_option("--camera", opts->camera,
                    "x,y,z,yaw,pitch: position in the files' units, yaw in degrees from +x "
                    "toward +y, pitch in degrees (positive up, -90 = straight down)");
    cmd->add_option("--path", opts->path,
                    "Camera path CSV (header x,y,z,yaw,pitch): one frame per row into --output/");
    cmd->add_option("--output", opts->output, "PNG file (--camera) or directory (--path)");
    cmd->add_option("--fov", opts->fov_deg, "Horizontal field of view in degrees")
        ->capture_default_str();
    cmd->add_option("--size", opts->size, "Image size WxH")->capture_default_str();
    cmd->add_option("--cell-size", opts->cell_size, "Finest cell edge in the files' units")
        ->capture_default_str();
    cmd->add_option("--levels", opts->levels, "Quadtree levels per section")->capture_default_str();
    cmd->add_option("--section-cells", opts->section_cells,
                    "Cells per side of a section's coarsest level (power of two)")
        ->capture_default_str();
    cmd->add_option("--sections", opts->sections, "Window of NxN sections around the camera")
        ->capture_default_str();
    cmd->add_option("--memory-budget", opts->memory_budget,
                    "Bytes for resident sections and read buffers (e.g. 256MB, 2GiB)")
        ->capture_default_str();
    cmd->add_option("--color", opts->color, "height | rgb | intensity | classification")
        ->capture_default_str();
    cmd->add_option("--height-stacks", opts->height_stacks,
                    "Up to K occupied height intervals per cell (2-8), so rays pass under "
                    "bridges, wires and tree crowns (0 = one column per cell)")
        ->capture_default_str();
    cmd->add_option("--stack-gap", opts->stack_gap,
                    "--height-stacks: vertical gap that separates intervals, in the files' units "
                    "(0 = 3 cells)")
        ->capture_default_str();
    cmd->add_option("--fog", opts->fog, "Fog distance in the files' units (0 = none)")
        ->capture_default_str();
    cmd->add_flag("--no-shading", opts->no_shading, "Flat colours, no normal shading");
    cmd->add_option("--threads", opts->threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    cmd->add_flag("--no-prefetch", opts->no_prefetch,
                  "--path: load each frame's sections only when it is due (no background "
                  "loading while the previous frame renders)");
    cmd->add_option("--mp4", opts->mp4,
                    "--path: also encode the frames into this MP4 (needs ffmpeg on PATH)");
    cmd->add_option("--fps", opts->fps, "Frame rate of the --mp4 video")->capture_default_str();
    cmd->add_flag("--interactive", opts->interactive,
                  "Open a window (GLFW/OpenGL): WASD/arrows/Q/E and mouse drag to fly, frame time "
                  "in the title; starts at --camera when given");
    cmd->add_option("--screenshot", opts->screenshot,
                    "--interactive: write the window's last frame (read back from OpenGL) to "
                    "this PNG and close");
    cmd->add_option("--frames", opts->frames,
                    "--interactive: close after this many frames (0 = when the window is closed)");
    cmd->add_flag("--quiet", opts->quiet, "No progress bar and no summary");
    cmd->add_flag("--progress", opts->progress,
                  "Show the progress bar even when not on a terminal");
    return [opts] { return run(*opts); };
}

}  // namespace beamtrace::cli
