#include "view_window.hpp"

#include "beamtrace/core/error.hpp"

#ifdef BEAMTRACE_HAVE_GLFW

#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <vector>

#include "beamtrace/io/png_writer.hpp"

namespace beamtrace::cli {
namespace {

/// The mouse and key state the GLFW callbacks write (reached through the window's user
/// pointer).
struct Input {
    bool dragging = false;
    double last_x = 0, last_y = 0;
    double drag_yaw_deg = 0, drag_pitch_deg = 0;  ///< accumulated since the last frame
    double speed_factor = 1.0;
};

Input& input_of(GLFWwindow* window) {
    return *static_cast<Input*>(glfwGetWindowUserPointer(window));
}

void on_mouse_button(GLFWwindow* window, int button, int action, int /*mods*/) {
    Input& in = input_of(window);
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
        in.dragging = action == GLFW_PRESS;
        glfwGetCursorPos(window, &in.last_x, &in.last_y);
    }
}

void on_cursor(GLFWwindow* window, double x, double y) {
    Input& in = input_of(window);
    if (in.dragging) {
        // Grab the scene: dragging right turns the camera left, dragging down tilts it up.
        in.drag_yaw_deg += 0.2 * (x - in.last_x);
        in.drag_pitch_deg += 0.2 * (y - in.last_y);
    }
    in.last_x = x;
    in.last_y = y;
}

void on_key(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
    if (action != GLFW_PRESS) {
        return;
    }
    Input& in = input_of(window);
    if (key == GLFW_KEY_ESCAPE) {
        glfwSetWindowShouldClose(window, GLFW_TRUE);
    } else if (key == GLFW_KEY_EQUAL || key == GLFW_KEY_KP_ADD) {
        in.speed_factor *= 2.0;
    } else if (key == GLFW_KEY_MINUS || key == GLFW_KEY_KP_SUBTRACT) {
        in.speed_factor /= 2.0;
    }
}

[[noreturn]] void fail_glfw(const std::string& what) {
    const char* description = nullptr;
    glfwGetError(&description);
    throw Error("view --interactive: " + what + ": " +
                (description != nullptr ? description : "unknown GLFW error") +
                " (is DISPLAY set? run headless under xvfb-run)");
}

/// glfwInit/glfwTerminate and the window, released in the right order.
class GlfwWindow {
  public:
    GlfwWindow(int width, int height) {
        if (glfwInit() != GLFW_TRUE) {
            fail_glfw("cannot initialise GLFW");
        }
        glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
        window_ = glfwCreateWindow(width, height, "beamtrace view", nullptr, nullptr);
        if (window_ == nullptr) {
            glfwTerminate();
            fail_glfw("cannot open a window");
        }
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(0);
    }
    ~GlfwWindow() {
        glfwDestroyWindow(window_);
        glfwTerminate();
    }
    GlfwWindow(const GlfwWindow&) = delete;
    GlfwWindow& operator=(const GlfwWindow&) = delete;
    [[nodiscard]] GLFWwindow* get() const { return window_; }

  private:
    GLFWwindow* window_ = nullptr;
};

/// Draws the image over the whole framebuffer (top row first in the image, bottom-up in GL).
void draw(GLFWwindow* window, const ViewImage& image) {
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    glViewport(0, 0, fb_w, fb_h);
    glClearColor(0.f, 0.f, 0.f, 1.f);
    glClear(GL_COLOR_BUFFER_BIT);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glRasterPos2f(-1.f, 1.f);
    glPixelZoom(static_cast<float>(fb_w) / static_cast<float>(image.width),
                -static_cast<float>(fb_h) / static_cast<float>(image.height));
    glDrawPixels(image.width, image.height, GL_RGB, GL_UNSIGNED_BYTE, image.rgb.data());
}

/// A 3 x 5 pixel font for the overlay: per glyph five rows of three bits (high bit left).
struct Glyph {
    char c;
    std::array<std::uint8_t, 5> rows;
};
constexpr std::array<Glyph, 20> kGlyphs = {{
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}},
    {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}},
    {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'m', {0, 0, 7, 7, 5}},
    {'s', {0, 3, 6, 3, 6}}, {'f', {3, 4, 6, 4, 4}}, {'p', {0, 7, 5, 7, 4}}, {'%', {5, 1, 2, 4, 5}},
    {'l', {6, 2, 2, 2, 7}}, {'o', {0, 7, 5, 5, 7}}, {'a', {0, 7, 1, 7, 7}}, {'d', {1, 7, 5, 5, 7}},
}};

/// Draws `text` (the glyphs above; others are blank) with its top-left corner at (x, y) in
/// framebuffer pixels from the top-left, each font pixel `scale` pixels wide, on a dark band.
void draw_text(int fb_w, int fb_h, int x, int y, int scale, const std::string& text) {
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0.0, fb_w, fb_h, 0.0, -1.0, 1.0);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    const int advance = 4 * scale;
    glColor3ub(0, 0, 0);
    glRecti(x - scale, y - scale, x + advance * static_cast<int>(text.size()) + scale,
            y + 6 * scale);
    glColor3ub(255, 255, 255);
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto* g = std::find_if(kGlyphs.begin(), kGlyphs.end(),
                                     [&](const Glyph& q) { return q.c == text[i]; });
        if (g == kGlyphs.end()) {
            continue;
        }
        const int gx = x + advance * static_cast<int>(i);
        for (int row = 0; row < 5; ++row) {
            for (int col = 0; col < 3; ++col) {
                if ((g->rows[static_cast<std::size_t>(row)] >> (2 - col)) & 1) {
                    glRecti(gx + col * scale, y + row * scale, gx + (col + 1) * scale,
                            y + (row + 1) * scale);
                }
            }
        }
    }
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
}

/// The overlay: frame time (top left) and, while sections load, a progress bar (bottom).
void draw_overlay(GLFWwindow* window, double frame_ms, const LoadStatus& status) {
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    const int scale = std::max(2, fb_h / 200);
    char text[64];
    std::snprintf(text, sizeof text, "%.1f ms %.1f fps", frame_ms,
                  frame_ms > 0 ? 1e3 / frame_ms : 0.0);
    std::string line = text;
    if (status.loading && status.points_total > 0) {
        line += " load " + std::to_string(100 * status.points_done / status.points_total) + "%";
        glMatrixMode(GL_PROJECTION);
        glLoadIdentity();
        glOrtho(0.0, fb_w, fb_h, 0.0, -1.0, 1.0);
        glColor3ub(255, 200, 0);
        const auto done =
            static_cast<double>(status.points_done) / static_cast<double>(status.points_total);
        glRecti(0, fb_h - 2 * scale, static_cast<int>(done * fb_w), fb_h);
        glLoadIdentity();
    }
    draw_text(fb_w, fb_h, 3 * scale, 3 * scale, scale, line);
}

/// Reads the back buffer (before the swap) and writes it as a PNG, top row first.
void save_screenshot(GLFWwindow* window, const std::string& path) {
    int fb_w = 0, fb_h = 0;
    glfwGetFramebufferSize(window, &fb_w, &fb_h);
    glFinish();
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    const auto row = static_cast<std::size_t>(fb_w) * 3;
    std::vector<std::uint8_t> pixels(row * static_cast<std::size_t>(fb_h));
    glReadPixels(0, 0, fb_w, fb_h, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
    if (glGetError() != GL_NO_ERROR) {
        throw OutputError(path + ": glReadPixels failed");
    }
    std::vector<std::uint8_t> flipped(pixels.size());
    for (std::size_t y = 0; y < static_cast<std::size_t>(fb_h); ++y) {
        std::copy_n(pixels.data() + (static_cast<std::size_t>(fb_h) - 1 - y) * row, row,
                    flipped.data() + y * row);
    }
    write_png_rgb8(path, fb_w, fb_h, flipped);
}

}  // namespace

bool view_window_available() {
    return true;
}

void require_view_window() {}

namespace {

/// Moves and turns the camera by the keys held and the mouse dragged over `dt` seconds; sets
/// `ahead` to where the camera will be in a few seconds at this speed (its sections load
/// ahead). Returns whether the camera changed.
bool steer(GLFWwindow* w, Input& input, double base_speed, double dt, ViewCamera& camera,
           Vec3d& ahead) {
    const auto key = [w](int k) { return glfwGetKey(w, k) == GLFW_PRESS; };
    const double speed = base_speed * input.speed_factor *
                         (key(GLFW_KEY_LEFT_SHIFT) || key(GLFW_KEY_RIGHT_SHIFT) ? 4.0 : 1.0) * dt;
    // Camera convention (docs/camera.md): positive yaw turns right, clockwise from above.
    const double yaw = camera.yaw_deg * std::numbers::pi / 180.0;
    const Vec3d forward(std::cos(yaw), -std::sin(yaw), 0.0);
    const Vec3d right(-std::sin(yaw), -std::cos(yaw), 0.0);
    Vec3d move;
    move += forward * ((key(GLFW_KEY_W) ? 1.0 : 0.0) - (key(GLFW_KEY_S) ? 1.0 : 0.0));
    move += right * ((key(GLFW_KEY_D) ? 1.0 : 0.0) - (key(GLFW_KEY_A) ? 1.0 : 0.0));
    move.z += (key(GLFW_KEY_E) || key(GLFW_KEY_PAGE_UP) ? 1.0 : 0.0) -
              (key(GLFW_KEY_Q) || key(GLFW_KEY_PAGE_DOWN) ? 1.0 : 0.0);
    const double turn = 60.0 * dt;
    const double yaw_change =
        ((key(GLFW_KEY_RIGHT) ? 1.0 : 0.0) - (key(GLFW_KEY_LEFT) ? 1.0 : 0.0)) * turn -
        input.drag_yaw_deg;
    const double pitch_change =
        ((key(GLFW_KEY_UP) ? 1.0 : 0.0) - (key(GLFW_KEY_DOWN) ? 1.0 : 0.0)) * turn +
        input.drag_pitch_deg;
    input.drag_yaw_deg = input.drag_pitch_deg = 0.0;
    constexpr double kLookAheadS = 3.0;
    ahead = camera.position + move * (dt > 0 ? speed / dt * kLookAheadS : 0.0);
    if (move.x == 0 && move.y == 0 && move.z == 0 && yaw_change == 0 && pitch_change == 0) {
        return false;
    }
    camera.position += move * speed;
    camera.yaw_deg = std::fmod(camera.yaw_deg + yaw_change + 360.0, 360.0);
    camera.pitch_deg = std::clamp(camera.pitch_deg + pitch_change, -89.9, 89.9);
    return true;
}

/// The frame time, the pose and the load in the window's title.
void set_title(GLFWwindow* w, double frame_ms, const ViewCamera& camera, const LoadStatus& status) {
    char title[256];
    std::snprintf(title, sizeof title,
                  "beamtrace view | %.1f ms/frame (%.1f fps) | %.0f, %.0f, %.0f yaw %.0f "
                  "pitch %.0f%s",
                  frame_ms, frame_ms > 0 ? 1e3 / frame_ms : 0.0, camera.position.x,
                  camera.position.y, camera.position.z, camera.yaw_deg, camera.pitch_deg,
                  status.loading ? " | loading sections" : "");
    std::string text = title;
    if (status.loading && status.points_total > 0) {
        text += " " + std::to_string(100 * status.points_done / status.points_total) + "%";
    }
    glfwSetWindowTitle(w, text.c_str());
}

/// Lets every section of the camera's window load, then draws and reads back that frame.
void write_screenshot(GLFWwindow* w, ViewSession& session, const ViewCamera& camera,
                      const RenderOptions& render, const std::string& path, ViewImage& image) {
    for (;;) {
        static_cast<void>(session.update(camera.position));
        if (session.load_status().sections == 0) {
            break;
        }
        session.finish_loading();
    }
    session.render(camera, render, image);
    draw(w, image);
    save_screenshot(w, path);
    glfwSwapBuffers(w);
}

}  // namespace

namespace {

/// One rendered frame of the window: for the log and the summary.
struct FrameRecord {
    bool moving = false;
    int step = 1;
    int width = 0, height = 0;
    double render_ms = 0.0;
    double frame_ms = 0.0;  ///< the whole loop iteration: input, loading, render, draw, swap
};

/// The --frame-log CSV, written at once (OutputError when it cannot be).
void write_frame_log(const std::string& path, const std::vector<FrameRecord>& records) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (f == nullptr) {
        throw OutputError(path + ": cannot write the frame log");
    }
    std::fprintf(f, "frame,moving,step,width,height,render_ms,frame_ms\n");
    for (std::size_t i = 0; i < records.size(); ++i) {
        const FrameRecord& r = records[i];
        std::fprintf(f, "%zu,%d,%d,%d,%d,%.3f,%.3f\n", i, r.moving ? 1 : 0, r.step, r.width,
                     r.height, r.render_ms, r.frame_ms);
    }
    if (std::fclose(f) != 0) {
        throw OutputError(path + ": cannot write the frame log");
    }
}

/// "moving: N frames, frame time median X ms (F fps), 95th Y ms; render median R ms; pixel
/// step a-b" for the frames that moved (or did not).
void print_frame_summary(const char* what, const std::vector<FrameRecord>& records, bool moving) {
    std::vector<double> frame_ms, render_ms;
    int lo = 0, hi = 0;
    for (const FrameRecord& r : records) {
        if (r.moving == moving) {
            frame_ms.push_back(r.frame_ms);
            render_ms.push_back(r.render_ms);
            lo = lo == 0 ? r.step : std::min(lo, r.step);
            hi = std::max(hi, r.step);
        }
    }
    const FrameTimeSummary f = summarize_frame_times(frame_ms);
    const FrameTimeSummary r = summarize_frame_times(render_ms);
    std::printf(
        "%s: %zu frames, frame time median %.1f ms (%.1f fps), 95th %.1f ms; render median %.1f "
        "ms; pixel step %d-%d\n",
        what, f.frames, f.median_ms, f.fps(), f.p95_ms, r.median_ms, lo, hi);
}

/// The camera's state in the frame loop: the scripted path, the input, the progressive step.
struct Flight {
    const WindowOptions& options;
    Input input;
    double base_speed = 0.0;
    std::size_t next_pose = 0;
    ProgressiveScaler scaler;
    int shown_step = 1;  ///< the pixel step of the frame on screen

    /// Advances the camera by the path or the input over `dt`; returns whether it moved.
    bool move(GLFWwindow* w, double dt, ViewCamera& camera, Vec3d& ahead) {
        if (next_pose < options.path.size()) {
            const Vec3d from = camera.position;
            camera.set_pose(options.path[next_pose++]);
            const Vec3d to = next_pose < options.path.size() ? options.path[next_pose].position
                                                             : camera.position;
            ahead = camera.position + (to - from) * 30.0;  // about a second ahead
            return true;
        }
        return steer(w, input, base_speed, dt, camera, ahead);
    }
};

/// After the loop: the screenshot (full resolution, every section loaded), the frame log and
/// the summary.
void finish_window(GLFWwindow* w, ViewSession& session, const ViewCamera& camera,
                   const RenderOptions& render, const WindowOptions& options, ViewImage& image,
                   const std::vector<FrameRecord>& records) {
    if (!options.screenshot.empty()) {
        write_screenshot(w, session, camera, render, options.screenshot, image);
    }
    if (!options.frame_log.empty()) {
        write_frame_log(options.frame_log, records);
    }
    if (options.quiet) {
        return;
    }
    double render_ms = 0.0;
    for (const FrameRecord& r : records) {
        render_ms += r.render_ms;
    }
    std::printf("%zu frames, %.1f ms per frame%s%s\n", records.size(),
                records.empty() ? 0.0 : render_ms / static_cast<double>(records.size()),
                options.screenshot.empty() ? "" : "; wrote ", options.screenshot.c_str());
    std::printf("window %dx%d, moving frames at most %.0f ms (pixel steps up to %d)\n",
                camera.width, camera.height, options.progressive.moving_frame_s * 1e3,
                options.progressive.max_step);
    print_frame_summary("moving", records, true);
    print_frame_summary("still", records, false);
}

}  // namespace

void run_view_window(ViewSession& session, ViewCamera camera, const RenderOptions& render,
                     const WindowOptions& options) {
    camera.validate();
    GlfwWindow window(camera.width, camera.height);
    GLFWwindow* w = window.get();
    Flight flight{options, {}, 0.0, 0, ProgressiveScaler(options.progressive), 1};
    glfwSetWindowUserPointer(w, &flight.input);
    glfwSetMouseButtonCallback(w, on_mouse_button);
    glfwSetCursorPosCallback(w, on_cursor);
    glfwSetKeyCallback(w, on_key);

    const Vec3d extent = session.sources().max() - session.sources().min();
    flight.base_speed = std::max(0.15 * std::max(extent.x, extent.y),
                                 20.0 * session.grid().config().cell_size);  // per second
    using Clock = std::chrono::steady_clock;
    ViewImage image;
    auto last = Clock::now();
    double frame_ms = 0.0;
    std::vector<FrameRecord> records;
    bool dirty = true;
    while (glfwWindowShouldClose(w) == GLFW_FALSE &&
           (options.frames <= 0 || static_cast<int>(records.size()) < options.frames)) {
        const auto now = Clock::now();
        const double dt = std::min(0.25, std::chrono::duration<double>(now - last).count());
        last = now;
        Vec3d ahead;
        const bool moving = flight.move(w, dt, camera, ahead);
        // Never waits for sections: adopts finished loads and starts new ones, for the
        // camera's window first, then for the window ahead. A coarse frame on screen is
        // refined once the camera stops.
        dirty = session.update(camera.position, ahead) || moving || dirty ||
                (!moving && flight.shown_step > 1);
        const LoadStatus status = session.load_status();
        bool rendered = false;
        if (dirty || status.loading || options.frames > 0) {
            const int step = flight.scaler.step(moving, camera.width, camera.height);
            const auto start = Clock::now();
            session.render(stepped_camera(camera, step), render, image);
            const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
            frame_ms = seconds * 1e3;
            records.push_back({moving, step, image.width, image.height, frame_ms, 0.0});
            flight.shown_step = step;
            rendered = true;
            dirty = false;
        }
        draw(w, image);
        draw_overlay(w, frame_ms, status);
        set_title(w, frame_ms, camera, status);
        glfwSwapBuffers(w);
        if (rendered) {
            FrameRecord& r = records.back();
            r.frame_ms = std::chrono::duration<double, std::milli>(Clock::now() - now).count();
            flight.scaler.record(
                static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height),
                r.render_ms * 1e-3, r.frame_ms * 1e-3);
        }
        if (!dirty && !status.loading && options.frames <= 0 && flight.shown_step == 1 &&
            flight.next_pose >= options.path.size()) {
            glfwWaitEventsTimeout(0.1);
        } else {
            glfwPollEvents();
        }
    }
    finish_window(w, session, camera, render, options, image, records);
}

}  // namespace beamtrace::cli

#else

namespace beamtrace::cli {

bool view_window_available() {
    return false;
}

void require_view_window() {
    throw ConfigError(
        "view --interactive: this beamtrace was built without GLFW/OpenGL (install "
        "libglfw3-dev, e.g. with scripts/install-deps.sh, and configure again)");
}

void run_view_window(ViewSession& /*session*/, ViewCamera /*camera*/,
                     const RenderOptions& /*render*/, const WindowOptions& /*options*/) {
    require_view_window();
}

}  // namespace beamtrace::cli

#endif
