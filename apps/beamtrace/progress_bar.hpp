// A progress bar on stderr: redrawn at most 10 times a second, only when stderr is a terminal
// (or when forced), and cleared when done.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace beamtrace::cli {

class ProgressBar {
  public:
    ProgressBar(std::string label, bool enabled);
    ~ProgressBar();
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    /// Draws `done` of `total` (at most every 0.1 s) with the rate since the last update with
    /// done == 0 (the start of the stage), or since construction.
    void update(std::size_t done, std::size_t total);
    void finish();

  private:
    std::string label_;
    bool enabled_;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point last_draw_;
};

/// True when stderr is a terminal.
[[nodiscard]] bool stderr_is_terminal();

}  // namespace beamtrace::cli
