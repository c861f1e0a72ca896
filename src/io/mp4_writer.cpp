#include "beamtrace/io/mp4_writer.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "beamtrace/core/error.hpp"

extern char** environ;

namespace beamtrace {
namespace {

/// Runs `argv` with stdin from `stdin_fd` (or /dev/null when -1) and stdout + stderr into
/// `log`; returns the child's pid. Throws OutputError (about `what`) when it cannot start.
pid_t spawn(const std::vector<std::string>& args, int stdin_fd, const std::filesystem::path& log,
            const std::string& what) {
    std::vector<char*> argv;
    for (const auto& a : args) {
        argv.push_back(const_cast<char*>(a.c_str()));
    }
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (stdin_fd >= 0) {
        posix_spawn_file_actions_adddup2(&actions, stdin_fd, 0);
    } else {
        posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    }
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
        throw OutputError(what + ": cannot run " + args[0] + ": " + std::strerror(rc));
    }
    return pid;
}

int wait_for(pid_t pid) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            return -1;
        }
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string last_line(const std::filesystem::path& log) {
    std::ifstream in(log);
    std::string line, last;
    while (std::getline(in, line)) {
        if (!line.empty()) {
            last = line;
        }
    }
    return last;
}

std::string read_all(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

std::optional<std::filesystem::path> find_ffmpeg() {
    const char* path = std::getenv("PATH");
    if (path == nullptr) {
        return std::nullopt;
    }
    std::stringstream dirs(path);
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        const std::filesystem::path candidate =
            std::filesystem::path(dir.empty() ? "." : dir) / "ffmpeg";
        if (::access(candidate.c_str(), X_OK) == 0 && std::filesystem::is_regular_file(candidate)) {
            return candidate;
        }
    }
    return std::nullopt;
}

Mp4Writer::Mp4Writer(std::filesystem::path final_path, int width, int height, double fps)
    : final_path_(std::move(final_path)), width_(width), height_(height) {
    const std::string what = final_path_.string();
    if (width < 1 || height < 1 || !(fps > 0)) {
        throw OutputError(what + ": bad video size " + std::to_string(width) + "x" +
                          std::to_string(height) + " or frame rate " + std::to_string(fps));
    }
    const auto ffmpeg = find_ffmpeg();
    if (!ffmpeg) {
        throw OutputError(what + ": writing an MP4 needs ffmpeg on PATH (apt install ffmpeg)");
    }
    const std::filesystem::path dir =
        final_path_.has_parent_path() ? final_path_.parent_path() : std::filesystem::path(".");
    const std::string stem =
        "." + final_path_.filename().string() + "." + std::to_string(::getpid());
    temp_path_ = dir / (stem + ".tmp");
    log_path_ = dir / (stem + ".log");

    // H.264 when this ffmpeg has libx264 (Debian's does), else MPEG-4 part 2.
    const pid_t probe = spawn({ffmpeg->string(), "-hide_banner", "-encoders"}, -1, log_path_, what);
    const bool x264 =
        wait_for(probe) == 0 && read_all(log_path_).find(" libx264 ") != std::string::npos;
    codec_ = x264 ? "libx264" : "mpeg4";

    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) {
        throw OutputError(what + ": cannot create a pipe: " + std::strerror(errno));
    }
    std::vector<std::string> args = {ffmpeg->string(),
                                     "-hide_banner",
                                     "-loglevel",
                                     "error",
                                     "-y",
                                     "-f",
                                     "rawvideo",
                                     "-pix_fmt",
                                     "rgb24",
                                     "-s",
                                     std::to_string(width) + "x" + std::to_string(height),
                                     "-r",
                                     std::to_string(fps),
                                     "-i",
                                     "-",
                                     "-vf",
                                     "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                     "-c:v",
                                     codec_};
    if (x264) {
        args.insert(args.end(), {"-preset", "veryfast", "-crf", "18"});
    } else {
        args.insert(args.end(), {"-q:v", "3"});
    }
    args.insert(args.end(), {"-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4",
                             temp_path_.string()});
    try {
        pid_ = spawn(args, fds[0], log_path_, what);
    } catch (...) {
        ::close(fds[0]);
        ::close(fds[1]);
        std::filesystem::remove(log_path_);
        throw;
    }
    ::close(fds[0]);
    pipe_ = fds[1];
}

Mp4Writer::~Mp4Writer() {
    if (!committed_) {
        if (pid_ > 0) {
            ::kill(pid_, SIGTERM);
        }
        finish();
        std::error_code ec;
        std::filesystem::remove(temp_path_, ec);
        std::filesystem::remove(log_path_, ec);
    }
}

int Mp4Writer::finish() {
    if (pipe_ >= 0) {
        ::close(pipe_);
        pipe_ = -1;
    }
    int status = -1;
    if (pid_ > 0) {
        status = wait_for(pid_);
        pid_ = -1;
    }
    return status;
}

void Mp4Writer::fail(const std::string& what) {
    const int status = finish();
    std::string message = final_path_.string() + ": " + what;
    const std::string ffmpeg_said = last_line(log_path_);
    if (!ffmpeg_said.empty()) {
        message += " (ffmpeg: " + ffmpeg_said + ")";
    } else if (status > 0) {
        message += " (ffmpeg exited with status " + std::to_string(status) + ")";
    }
    throw OutputError(message);
}

void Mp4Writer::write(std::span<const std::uint8_t> rgb) {
    const std::size_t size =
        static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 3;
    if (rgb.size() != size || pipe_ < 0) {
        throw OutputError(final_path_.string() + ": frame of " + std::to_string(rgb.size()) +
                          " bytes, expected " + std::to_string(size));
    }
    // A pipe whose reader died raises SIGPIPE: block it on this thread while writing, and
    // consume it if it came, so a failed ffmpeg is an error message, not a dead process.
    sigset_t pipe_set, old;
    sigemptyset(&pipe_set);
    sigaddset(&pipe_set, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_set, &old);
    std::size_t done = 0;
    int error = 0;
    while (done < size) {
        const ::ssize_t n = ::write(pipe_, rgb.data() + done, size - done);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0) {
            error = errno;
            break;
        }
        done += static_cast<std::size_t>(n);
    }
    if (error == EPIPE) {
        const timespec zero = {0, 0};
        sigtimedwait(&pipe_set, nullptr, &zero);
    }
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    if (error != 0) {
        fail(std::string("writing frame ") + std::to_string(frames_) +
             " to ffmpeg failed: " + std::strerror(error));
    }
    ++frames_;
}

void Mp4Writer::commit() {
    if (committed_) {
        return;
    }
    const int status = finish();
    if (status != 0) {
        fail("ffmpeg failed");
    }
    std::error_code ec;
    std::filesystem::rename(temp_path_, final_path_, ec);
    if (ec) {
        fail("cannot rename " + temp_path_.string() + ": " + ec.message());
    }
    std::filesystem::remove(log_path_, ec);
    committed_ = true;
}

}  // namespace beamtrace
