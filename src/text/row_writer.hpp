// Text tables written row by row: rows are formatted in place into a buffer that goes to an
// AtomicFile about 1 MiB at a time (the CSV writers).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

#include "beamtrace/core/atomic_file.hpp"

namespace beamtrace::detail {

/// Writes a header line, then rows formatted straight into the buffer:
///
///     char* p = rows.row();
///     p = std::to_chars(p, rows.end(), value).ptr;
///     *p++ = '\n';
///     rows.end_row(p);
///
/// and finally commit(). A row must not take more than `max_row_bytes`: nothing checks for room
/// while it is formatted. As with AtomicFile, nothing appears at `path` without commit().
class RowWriter {
  public:
    RowWriter(const std::filesystem::path& path, std::string_view header, std::size_t max_row_bytes)
        : out_(path), buffer_(kChunkBytes + max_row_bytes, '\0') {
        out_.write(header);
        out_.write("\n", 1);
    }

    /// Where the next row starts; at least `max_row_bytes` bytes lie before end().
    [[nodiscard]] char* row() { return buffer_.data() + used_; }
    [[nodiscard]] char* end() { return buffer_.data() + buffer_.size(); }

    /// Ends the row written from row() up to `p` (one past its last byte).
    void end_row(char* p) {
        used_ = static_cast<std::size_t>(p - buffer_.data());
        if (used_ >= kChunkBytes) {
            out_.write(buffer_.data(), used_);
            used_ = 0;
        }
    }

    /// Writes the buffered rows and publishes the file.
    void commit() {
        out_.write(buffer_.data(), used_);
        used_ = 0;
        out_.commit();
    }

  private:
    static constexpr std::size_t kChunkBytes = std::size_t{1} << 20;

    AtomicFile out_;
    std::string buffer_;
    std::size_t used_ = 0;
};

}  // namespace beamtrace::detail
