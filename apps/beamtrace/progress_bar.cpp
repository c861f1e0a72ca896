#include "progress_bar.hpp"

#include <unistd.h>

#include <cstdio>

namespace beamtrace::cli {

bool stderr_is_terminal() {
    return ::isatty(STDERR_FILENO) != 0;
}

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

ProgressBar::~ProgressBar() {
    finish();
}

void ProgressBar::update(std::size_t done, std::size_t total) {
    if (!enabled_ || total == 0) {
        return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (done == 0) {
        // The work proper starts now (loading and building came before): the rate counts
        // from here.
        start_ = now;
        return;
    }
    if (done < total && now - last_draw_ < std::chrono::milliseconds(100)) {
        return;
    }
    last_draw_ = now;
    const double frac = static_cast<double>(done) / static_cast<double>(total);
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
    const double left = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %5.1f%%  %.2f M/s  %.0f s left ", label_.c_str(), bar.c_str(),
                 100.0 * frac, rate / 1e6, left);
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressBar::finish() {
    if (drawn_) {
        std::fprintf(stderr, "\n");
        std::fflush(stderr);
        drawn_ = false;
    }
}

}  // namespace beamtrace::cli
