// Write a file so that it appears under its final name complete or not at all.
#pragma once

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string_view>

namespace beamtrace {

/// Writes `<dir>/.<name>.<pid>.tmp` (or `.<name>.<pid>-<k>.tmp` when that name is taken) and
/// renames it onto `<dir>/<name>` in commit(). If the object is destroyed before a successful
/// commit() — an exception, an early return — the temporary file is removed and whatever was at
/// the final path before is left untouched. Writes go through a 1 MiB stdio buffer.
///
/// All failures throw OutputError naming the final path and the system's reason.
class AtomicFile {
  public:
    /// Creates the temporary file. With `fsync_on_commit`, commit() also waits until the data
    /// has reached the disk before renaming (slower; for outputs that must survive power loss).
    explicit AtomicFile(std::filesystem::path final_path, bool fsync_on_commit = false);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;
    AtomicFile(AtomicFile&&) = delete;
    AtomicFile& operator=(AtomicFile&&) = delete;

    /// Appends `size` bytes.
    void write(const void* data, std::size_t size);
    void write(std::string_view text) { write(text.data(), text.size()); }

    /// Flushes, checks for write errors, optionally fsyncs, closes and renames the temporary file
    /// onto the final path. Afterwards the object accepts no more writes.
    void commit();

    /// The open stream, for C libraries that write to a `FILE*` (libpng). Errors on it are
    /// detected by commit(). Null after commit().
    [[nodiscard]] std::FILE* stream() const { return file_; }
    [[nodiscard]] const std::filesystem::path& path() const { return final_path_; }
    [[nodiscard]] const std::filesystem::path& temp_path() const { return temp_path_; }
    [[nodiscard]] bool committed() const { return committed_; }

  private:
    [[noreturn]] void fail(std::string_view action, int error_number) const;

    std::filesystem::path final_path_;
    std::filesystem::path temp_path_;
    std::unique_ptr<char[]> buffer_;
    std::FILE* file_ = nullptr;
    bool fsync_on_commit_ = false;
    bool committed_ = false;
};

}  // namespace beamtrace
