// A file of known size that several threads write at once, each its own byte ranges at known
// offsets; it appears under its final name complete or not at all.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string_view>

#include "beamtrace/core/atomic_file.hpp"

namespace beamtrace {

/// The temporary file of an AtomicFile written with pwrite(2) at offsets (no shared stream, no
/// lock of ours: any thread, ranges that do not overlap). With `reserve_bytes`, its blocks are
/// reserved up front (posix_fallocate): a full disk or a quota is an OutputError here, before
/// anything is written. commit() closes and renames it; destroyed before, it removes the
/// temporary file (as AtomicFile does) and leaves what was at the final path untouched.
///
/// Failures throw OutputError naming the final path, the step and the system's reason.
class ParallelFile {
  public:
    explicit ParallelFile(const std::filesystem::path& final_path, std::uint64_t reserve_bytes = 0);

    /// Writes `bytes` at `offset`.
    void write_at(std::string_view bytes, std::uint64_t offset) const;
    /// Closes the file and renames it onto the final path.
    void commit() { file_.commit(); }

    [[nodiscard]] const std::filesystem::path& path() const { return file_.path(); }
    [[nodiscard]] const std::filesystem::path& temp_path() const { return file_.temp_path(); }

  private:
    AtomicFile file_;
    int fd_;
};

/// Fills one byte range of a ParallelFile, in order, from a small buffer that stays in the
/// cache. The bytes go out in blocks that end on multiples of kBlock in the file, so that the
/// kernel fills whole, large page-cache folios with one copy: no page is zeroed first (as a page
/// of a shared mapping is on its first store) or read back (as a partly written one is).
///
/// The writer stores at most kSlack bytes at a time at `at` (from begin()), calls
/// `at = flush(at)` whenever `at` has reached limit(), and finish(at) at the end.
class StagedRange {
  public:
    static constexpr std::size_t kBlock = std::size_t{1} << 16;
    static constexpr std::size_t kSlack = 4096;

    StagedRange(const ParallelFile& file, std::uint64_t offset);

    [[nodiscard]] char* begin() const { return buffer_.get(); }
    /// Where the current block ends: the next multiple of kBlock in the file.
    [[nodiscard]] char* limit() const {
        return begin() + static_cast<std::size_t>((offset_ / kBlock + 1) * kBlock - offset_);
    }
    /// When `at` has reached limit(): writes out the block, moves the bytes past it to begin()
    /// and returns where the next bytes go. Else returns `at`.
    [[nodiscard]] char* flush(char* at);
    /// Writes out the bytes [begin(), at).
    void finish(const char* at);

  private:
    const ParallelFile& file_;
    std::uint64_t offset_;  ///< of begin() in the file
    std::unique_ptr<char[]> buffer_;
};

}  // namespace beamtrace
