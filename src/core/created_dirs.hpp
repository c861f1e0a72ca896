// The folders a run creates for its outputs, removed again when the run fails or is interrupted:
// a run that writes nothing leaves the file system as it found it.
#pragma once

#include <filesystem>
#include <system_error>
#include <vector>

namespace beamtrace {

/// Notes which of `dir` and its parents do not exist yet (construct it before creating them).
/// Unless keep() is called, the destructor removes those folders, deepest first, each only if
/// it is empty: files put there by others, or left by the run's own committed outputs, stay.
class CreatedDirs {
  public:
    explicit CreatedDirs(const std::filesystem::path& dir) {
        std::error_code ec;
        for (std::filesystem::path p = dir; !p.empty() && !std::filesystem::exists(p, ec);
             p = p.parent_path()) {
            if (ec || p == p.parent_path()) {
                break;
            }
            missing_.push_back(p);  // deepest first
        }
    }
    ~CreatedDirs() {
        for (const auto& p : missing_) {
            std::error_code ec;
            if (!std::filesystem::is_directory(p, ec) || !std::filesystem::is_empty(p, ec) ||
                !std::filesystem::remove(p, ec)) {
                return;  // a parent of a folder that stays stays too
            }
        }
    }
    CreatedDirs(const CreatedDirs&) = delete;
    CreatedDirs& operator=(const CreatedDirs&) = delete;

    /// The run succeeded: the folders stay.
    void keep() { missing_.clear(); }

  private:
    std::vector<std::filesystem::path> missing_;
};

}  // namespace beamtrace
