// What every fuzz harness of fuzz/ shares: a per-process scratch folder for the loaders that read
// a path, and the rule that only beamtrace errors are expected rejections.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "beamtrace/core/error.hpp"

namespace beamtrace::fuzz {

/// A folder of its own under the system temp folder, removed with everything in it when the
/// object is destroyed (at exit for the one scratch_dir() returns).
class ScratchDir {
  public:
    ScratchDir()
        : path_(std::filesystem::temp_directory_path() /
                ("beamtrace-fuzz-" + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    ScratchDir(ScratchDir&&) = delete;
    ScratchDir& operator=(ScratchDir&&) = delete;

    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

  private:
    std::filesystem::path path_;
};

/// This process's scratch folder (made on first use).
inline const std::filesystem::path& scratch_dir() {
    static const ScratchDir dir;
    return dir.path();
}

/// Writes the input to scratch_dir()/name (replacing what was there) and returns its path.
inline std::filesystem::path write_input(const std::uint8_t* data, std::size_t size,
                                         const std::string& name) {
    const std::filesystem::path path = scratch_dir() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out.flush()) {
        throw std::runtime_error("fuzz harness: cannot write " + path.string());
    }
    return path;
}

/// The input as text (YAML parsers take a string).
inline std::string as_text(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

/// Runs `body`; a beamtrace::Error is the expected rejection of a bad input and is swallowed
/// (printed when BEAMTRACE_FUZZ_SHOW_REJECTIONS is set: the replay's -v, to see that the seeds
/// are accepted). Anything else (another exception, a crash, a sanitizer report) escapes, so that
/// libFuzzer and the corpus replay report it.
template <class Body>
int run_guarded(Body&& body) {
    try {
        body();
        if (std::getenv("BEAMTRACE_FUZZ_SHOW_REJECTIONS") != nullptr) {
            std::cerr << "  accepted\n";
        }
    } catch (const beamtrace::Error& e) {
        if (std::getenv("BEAMTRACE_FUZZ_SHOW_REJECTIONS") != nullptr) {
            std::cerr << "  rejected: " << e.what() << "\n";
        }
    }
    return 0;
}

}  // namespace beamtrace::fuzz
