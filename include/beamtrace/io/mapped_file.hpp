// A file of known size written in place, through a shared memory mapping, by several threads at
// once; it appears under its final name complete or not at all.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>

#include "beamtrace/core/atomic_file.hpp"

namespace beamtrace {

/// Creates the temporary file of an AtomicFile, reserves its `size` bytes on the disk
/// (posix_fallocate: a full disk or a quota is an OutputError here, never a SIGBUS while the
/// mapping is written) and maps them shared and writable. Threads write their own byte ranges of
/// bytes() straight into the page cache: no buffer, no copy by write(2). commit() unmaps, closes
/// and renames; destroyed before, it removes the temporary file (as AtomicFile does).
///
/// On a file system that cannot map files (mmap fails), or with `buffered`, bytes() is memory of
/// its own instead, written to the file by commit(): the same bytes, a copy slower.
///
/// Failures throw OutputError naming the final path, the step and the system's reason.
class MappedFile {
  public:
    MappedFile(const std::filesystem::path& final_path, std::size_t size, bool buffered = false);
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;
    MappedFile(MappedFile&&) = delete;
    MappedFile& operator=(MappedFile&&) = delete;

    /// The file's bytes (zero until written); empty after commit().
    [[nodiscard]] std::span<char> bytes() const { return {data_, size_}; }
    /// Whether bytes() is the file's mapping (false: a buffer written by commit()).
    [[nodiscard]] bool mapped() const { return buffer_ == nullptr; }
    /// Asks the kernel to back bytes [offset, offset + length) with writable pages in one call,
    /// before a thread fills them (one fault-in for the range instead of one fault a page). A
    /// hint only: nothing happens where the range is not mapped or the kernel lacks it.
    void prefault(std::size_t offset, std::size_t length) const noexcept;
    /// Unmaps (or writes the buffer), closes and renames the file onto its final path.
    void commit();

    [[nodiscard]] const std::filesystem::path& path() const { return file_.path(); }
    [[nodiscard]] const std::filesystem::path& temp_path() const { return file_.temp_path(); }

  private:
    void unmap() noexcept;
    void write_buffer() const;

    AtomicFile file_;       ///< the temporary name, its removal and the rename
    int fd_ = -1;           ///< the temporary file opened read-write (mmap needs it)
    char* data_ = nullptr;  ///< the mapping, or buffer_
    std::size_t size_ = 0;
    std::unique_ptr<char[]> buffer_;
};

}  // namespace beamtrace
