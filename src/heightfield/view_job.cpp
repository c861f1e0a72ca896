#include "beamtrace/heightfield/view_job.hpp"

#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <utility>

#include "beamtrace/core/error.hpp"
#include "beamtrace/heightfield/camera_path.hpp"
#include "beamtrace/heightfield/data_framing.hpp"
#include "beamtrace/io/mp4_writer.hpp"
#include "beamtrace/io/png_writer.hpp"
#include "core/created_dirs.hpp"

namespace beamtrace {
namespace {

/// The power of ten or two of a size unit; 0 when unknown.
double unit_factor(std::string unit) {
    for (auto& c : unit) {
        c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    if (unit.empty() || unit == "B") {
        return 1;
    }
    if (unit == "KB" || unit == "K") {
        return 1e3;
    }
    if (unit == "MB" || unit == "M") {
        return 1e6;
    }
    if (unit == "GB" || unit == "G") {
        return 1e9;
    }
    if (unit == "KIB") {
        return 1024.0;
    }
    if (unit == "MIB") {
        return 1024.0 * 1024.0;
    }
    return unit == "GIB" ? 1024.0 * 1024.0 * 1024.0 : 0.0;
}

/// Checks of the one-image and fly-through modes.
void check_offline(const ViewJobConfig& c, std::vector<std::string>& problems) {
    if (c.pose.has_value() && !c.path.empty()) {
        problems.emplace_back(
            "view: give one of --camera x,y,z,yaw,pitch and --path FILE.csv, not both (neither: "
            "an overview of all the data)");
    }
    if (c.output.empty()) {
        problems.emplace_back("view: --output is required (a PNG file, or a folder with --path)");
    }
    if (!c.screenshot.empty() || c.frames != 0 || !c.frame_log.empty()) {
        problems.emplace_back("view: --screenshot, --frames and --frame-log go with --interactive");
    }
}

}  // namespace

std::vector<std::string> ViewJobConfig::validate() const {
    std::vector<std::string> problems;
    if (interactive) {
        if (pose.has_value() && !path.empty()) {
            problems.emplace_back(
                "view: --interactive starts at --camera or flies --path, not both");
        }
        const auto more = progressive.validate();
        problems.insert(problems.end(), more.begin(), more.end());
    } else {
        check_offline(*this, problems);
    }
    if (!mp4.empty()) {
        if (path.empty() || interactive) {
            problems.emplace_back(
                "view: --mp4 goes with --path (a fly-through), not --interactive");
        }
        if (!(fps > 0) || !std::isfinite(fps)) {
            problems.push_back("view: --fps " + std::to_string(fps) + " is not positive");
        }
    }
    if (frames < 0) {
        problems.push_back("view: --frames " + std::to_string(frames) + " is negative");
    }
    if (!(render.eye_dome >= 0.0) || !std::isfinite(render.eye_dome)) {
        problems.push_back("view: --eye-dome " + std::to_string(render.eye_dome) +
                           " is not a number >= 0");
    }
    return problems;
}

std::vector<CameraPose> ViewJobConfig::poses() const {
    if (pose) {
        return {*pose};
    }
    if (!path.empty()) {
        return read_camera_path(path);
    }
    return {};
}

namespace {

/// Frame i's PNG: job.output (one camera) or frame_NNNNN.png in it (a path).
std::filesystem::path frame_file(const ViewJobConfig& job, std::size_t i) {
    std::filesystem::path file = job.output;
    if (!job.path.empty()) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05zu.png", i);
        file /= name;
    }
    return file;
}

/// What the frames of one run_view_frames share: the session, the camera, the image buffers
/// (reused frame after frame), the video and the files written so far.
struct FrameLoop {
    const ViewJobConfig& job;
    ViewSession& session;
    const std::vector<CameraPose>& poses;
    const ViewFrameHooks& hooks;
    Mp4Writer* video = nullptr;
    ViewCamera camera;
    ViewImage image;
    ViewFramesResult result;
    std::vector<std::filesystem::path> written;

    /// Loads, renders and writes frame i (checking job.cancel between the steps).
    void run(std::size_t i) {
        throw_if_cancelled(job.cancel, "view");
        camera.set_pose(poses[i]);
        ViewFrame frame;
        frame.index = i;
        // Waits for the sections prefetched while the previous frame rendered, then loads
        // whatever did not fit next to them: frame i is the same as without prefetching.
        frame.stats = session.move_to(camera.position, [&](std::uint64_t done, std::uint64_t n) {
            if (hooks.loading) {
                hooks.loading(i, done, n);
            }
        });
        result.prefetched += frame.stats.sections_prefetched;
        if (i + 1 < poses.size() && job.prefetch) {
            session.prefetch(poses[i + 1].position);  // loads on the loader thread meanwhile
        }
        throw_if_cancelled(job.cancel, "view");
        const auto start = std::chrono::steady_clock::now();
        session.render(camera, job.render, image);
        result.render_s +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        frame.file = frame_file(job, i);
        throw_if_cancelled(job.cancel, "view");
        write_png_rgb8(frame.file, image.width, image.height, image.rgb);
        written.push_back(frame.file);
        if (video != nullptr) {
            video->write(image.rgb);
        }
        frame.image = &image;
        frame.render_s = result.render_s;
        if (hooks.written) {
            hooks.written(frame);
        }
    }
};

}  // namespace

ViewFramesResult run_view_frames(const ViewJobConfig& job, ViewSession& session,
                                 const std::vector<CameraPose>& poses,
                                 const ViewFrameHooks& hooks) {
    throw_if_cancelled(job.cancel, "view");
    std::optional<CreatedDirs> created;  // removed again when a failure leaves it empty
    if (!job.path.empty()) {
        created.emplace(job.output);
        std::error_code ec;
        std::filesystem::create_directories(job.output, ec);
        if (ec) {
            throw OutputError(job.output.string() + ": cannot create directory: " + ec.message());
        }
    }
    std::unique_ptr<Mp4Writer> video;  // removes its temporary file unless committed
    if (!job.mp4.empty()) {
        video = std::make_unique<Mp4Writer>(job.mp4, job.camera.width, job.camera.height, job.fps);
    }
    std::vector<CameraPose> overview;
    if (poses.empty() && job.path.empty()) {
        const PointsBox box = points_box(session.sources());
        overview.push_back(overview_camera(box.lo, box.hi, job.camera).pose());
    }
    FrameLoop loop{job,   session,     overview.empty() ? poses : overview,
                   hooks, video.get(), job.camera,
                   {},    {},          {}};
    try {
        for (std::size_t i = 0; i < loop.poses.size(); ++i) {
            loop.run(i);
        }
        throw_if_cancelled(job.cancel, "view");
    } catch (const Interrupted&) {
        for (const auto& f : loop.written) {  // an interrupted view writes nothing
            std::error_code ignored;
            std::filesystem::remove(f, ignored);
        }
        throw;
    }
    ViewFramesResult result = loop.result;
    result.frames = loop.poses.size();
    if (video) {
        video->commit();
        result.mp4_frames = video->frames();
        result.mp4_codec = video->codec();
    }
    if (created) {
        created->keep();
    }
    return result;
}

std::uint64_t parse_byte_size(std::string_view text) {
    const std::string s(text);
    std::size_t used = 0;
    double value = 0;
    try {
        value = std::stod(s, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    const double factor = unit_factor(s.substr(used));
    if (used == 0 || factor == 0 || !(value > 0) || !std::isfinite(value * factor)) {
        throw ConfigError("memory budget '" + s + "' is not a size such as 256MB, 2GB or 512MiB");
    }
    return static_cast<std::uint64_t>(value * factor);
}

std::string byte_size_text(std::uint64_t bytes) {
    for (const auto& [factor, unit] :
         {std::pair<std::uint64_t, const char*>{1000000000, "GB"}, {1000000, "MB"}, {1000, "KB"}}) {
        if (bytes > 0 && bytes % factor == 0) {
            return std::to_string(bytes / factor) + unit;
        }
    }
    return std::to_string(bytes);
}

void parse_size_pair(std::string_view text, std::string_view what, int& w, int& h) {
    const auto x = text.find('x');
    const auto num = [](std::string_view s, int& out) {
        const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
        return !s.empty() && ec == std::errc() && ptr == s.data() + s.size() && out >= 1;
    };
    int a = 0, b = 0;
    if (x == std::string_view::npos || !num(text.substr(0, x), a) || !num(text.substr(x + 1), b)) {
        throw ConfigError(std::string(what) + " '" + std::string(text) +
                          "' is not of the form WxH with positive integers");
    }
    w = a;
    h = b;
}

int parse_section_window(std::string_view text) {
    int sx = 0, sy = 0;
    parse_size_pair(text, "--sections", sx, sy);
    if (sx != sy) {
        throw ConfigError("--sections '" + std::string(text) + "' must be square (NxN)");
    }
    return sx;
}

}  // namespace beamtrace
