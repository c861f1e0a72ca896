// MP4 videos from raw RGB frames, encoded by an `ffmpeg` found on PATH (no library dependency).
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

namespace beamtrace {

/// The first executable `ffmpeg` in the directories of $PATH, if any.
[[nodiscard]] std::optional<std::filesystem::path> find_ffmpeg();

/// Pipes frames to `ffmpeg -f rawvideo -pix_fmt rgb24 ... -pix_fmt yuv420p` (H.264 with libx264
/// when ffmpeg has it, else MPEG-4 part 2) writing `.<name>.<pid>.tmp` next to the final path;
/// commit() waits for ffmpeg and renames the file onto the final path, so a video appears
/// complete or not at all. Odd sizes are padded by one black row/column (yuv420p needs even
/// sizes). Throws OutputError naming the path (and ffmpeg's last message) when ffmpeg is
/// missing, fails or exits early.
class Mp4Writer {
  public:
    Mp4Writer(std::filesystem::path final_path, int width, int height, double fps);
    /// Without a commit(): stops ffmpeg and removes the temporary file.
    ~Mp4Writer();
    Mp4Writer(const Mp4Writer&) = delete;
    Mp4Writer& operator=(const Mp4Writer&) = delete;

    /// One frame: width * height * 3 bytes, top row first.
    void write(std::span<const std::uint8_t> rgb);
    void commit();
    [[nodiscard]] const std::string& codec() const { return codec_; }
    [[nodiscard]] int frames() const { return frames_; }

  private:
    [[noreturn]] void fail(const std::string& what);
    /// Closes the pipe and waits for ffmpeg; its exit status (-1: killed).
    int finish();

    std::filesystem::path final_path_, temp_path_, log_path_;
    int width_ = 0, height_ = 0;
    std::string codec_;
    int pipe_ = -1;
    pid_t pid_ = -1;
    int frames_ = 0;
    bool committed_ = false;
};

}  // namespace beamtrace
