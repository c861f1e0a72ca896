// A file whose header holds the count of what follows it (PLY, PCD), written without holding
// the body in memory: the body streams to a temporary file, and commit() writes the header and
// copies the body after it into the final file (atomically: temporary file + rename).
#pragma once

#include <filesystem>
#include <memory>
#include <string_view>

#include "beamtrace/core/atomic_file.hpp"

namespace beamtrace::detail {

class CountedFile {
  public:
    /// Creates the body's temporary file next to `path`. Throws OutputError.
    explicit CountedFile(std::filesystem::path path);
    /// Appends body bytes.
    void append(std::string_view bytes) { body_->write(bytes); }
    /// Writes `header` then the body to `path`, renames it into place and removes the body.
    void commit(std::string_view header);
    /// Removes the body; nothing appears under `path`.
    void abort() noexcept { body_.reset(); }
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

  private:
    std::filesystem::path path_;
    std::unique_ptr<AtomicFile> body_;  ///< never committed: its temporary file is removed
};

}  // namespace beamtrace::detail
