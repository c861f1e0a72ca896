// Appends bytes to a file in large, aligned writes that bypass the page cache (O_DIRECT) where
// the file system allows it: a survey writes hundreds of MB, and copying them into the page cache
// costs as much CPU as tracing them. Elsewhere (tmpfs, ...) the same writes go through the cache.
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace beamtrace::detail {

class DirectSink {
  public:
    /// Opens a second descriptor on `path` (an existing, empty file that the caller also holds
    /// open as `stream`); appends start at offset 0. Throws OutputError naming `display`.
    DirectSink(const std::filesystem::path& path, std::filesystem::path display);
    ~DirectSink();
    DirectSink(const DirectSink&) = delete;
    DirectSink& operator=(const DirectSink&) = delete;

    void append(const void* data, std::size_t size);
    /// Writes what is still staged: the aligned part directly, the tail through `stream` (which
    /// is left positioned at the end of the data). No appends afterwards.
    void finish(std::FILE* stream);
    /// Bytes appended so far.
    [[nodiscard]] std::uint64_t size() const { return offset_ + used_; }
    /// True when writes bypass the page cache: the descriptor's flags, as the kernel reports
    /// them (fcntl F_GETFL), have O_DIRECT.
    [[nodiscard]] bool direct() const { return direct_; }
    /// Bytes written so far through the O_DIRECT descriptor (the rest went through the page
    /// cache): which write path ran, for tests and reports.
    [[nodiscard]] std::uint64_t direct_bytes() const { return direct_bytes_; }

  private:
    void write_aligned(std::size_t bytes);
    [[noreturn]] void fail(const char* what, int error_number) const;

    std::filesystem::path path_, display_;
    int fd_ = -1;
    bool direct_ = false;
    struct Free {
        void operator()(char* p) const;
    };
    std::unique_ptr<char, Free> stage_;
    std::size_t used_ = 0;      ///< bytes staged
    std::uint64_t offset_ = 0;  ///< file offset of stage_[0] (a multiple of kAlign)
    std::uint64_t direct_bytes_ = 0;
};

}  // namespace beamtrace::detail
