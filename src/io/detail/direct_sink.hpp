// Appends bytes to a file in large, aligned writes that bypass the page cache (O_DIRECT) where
// the file system allows it: a survey writes hundreds of MB, and copying them into the page cache
// costs as much CPU as tracing them. Elsewhere (tmpfs, ...) the same writes go through the cache.
// The writes run on a thread of their own, a few stages behind the appends: a direct write
// waits for the disk, and the appending thread (a survey's pool thread) must not. Where the disk
// falls behind (every stage still queued), a stage goes through the page cache instead, written
// at once by the appending thread: the file's bytes are the same, and nothing waits for the disk.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace beamtrace::detail {

class DirectSink {
  public:
    /// Bytes of one stage: what one direct write takes (a multiple of every logical block size).
    static constexpr std::size_t kStageBytes = std::size_t{1} << 20;
    /// Stages at most: one being filled, the others written or waiting to be (the memory bound).
    static constexpr std::size_t kStages = 8;

    /// Opens a second descriptor on `path` (an existing, empty file that the caller also holds
    /// open as `stream`); appends start at offset 0. Throws OutputError naming `display`.
    /// `before_write`, when set, runs on the writing thread before each stage's write (a seam
    /// for tests: a slow disk on demand).
    DirectSink(const std::filesystem::path& path, std::filesystem::path display,
               std::function<void()> before_write = {});
    ~DirectSink();
    DirectSink(const DirectSink&) = delete;
    DirectSink& operator=(const DirectSink&) = delete;

    /// Copies the bytes into the stage; a full stage goes to the writing thread, or, when every
    /// stage is still queued, through the page cache at once. Throws OutputError when a write
    /// failed (this one, or an earlier one on the writing thread).
    void append(const void* data, std::size_t size);
    /// Writes the stages still queued through the page cache, waits for the one being written,
    /// then writes the last, partly filled one through `stream` (the stream is left positioned
    /// at the end of the data). No appends afterwards.
    void finish(std::FILE* stream);
    /// Bytes appended so far.
    [[nodiscard]] std::uint64_t size() const { return offset_ + used_; }
    /// After finish(): true when the stages' writes bypassed the page cache: the descriptor's
    /// flags, as the kernel reports them (fcntl F_GETFL), have O_DIRECT.
    [[nodiscard]] bool direct() const { return direct_; }
    /// After finish(): bytes written through the O_DIRECT descriptor (the rest went through the
    /// page cache): which write path ran, for tests and reports.
    [[nodiscard]] std::uint64_t direct_bytes() const { return direct_bytes_; }
    /// Bytes of whole stages written through the page cache because the disk was behind (or
    /// still queued at finish()); with direct_bytes() and the last stage, every byte appended.
    [[nodiscard]] std::uint64_t spilled_bytes() const { return spilled_bytes_; }

  private:
    struct Free {
        void operator()(char* p) const;
    };
    using Stage = std::unique_ptr<char, Free>;
    struct Job {
        Stage stage;
        std::uint64_t offset = 0;
    };

    /// Hands the full stage to the writing thread and takes an empty one, or spills it.
    void submit();
    /// The writing thread: writes the queued stages in order, then returns them.
    void run_writes();
    /// Writes a whole stage at `offset`; false (errno kept) on an error.
    bool write_stage(const char* data, std::uint64_t offset);
    /// Writes a whole stage at `offset` through the page cache, on the calling thread.
    void spill(const char* data, std::uint64_t offset);
    /// Writes the queued stages through the page cache, stops the writing thread (when it has
    /// written the stage it holds); rethrows the first error.
    void stop_writes();
    /// Throws OutputError when a write failed (error_ set).
    void check_error();
    [[noreturn]] void fail(const char* what, int error_number) const;

    std::filesystem::path path_, display_;
    std::function<void()> before_write_;
    int fd_ = -1;  ///< the writing thread's while it runs
    bool direct_ = false;
    std::uint64_t direct_bytes_ = 0;
    int buffered_fd_ = -1;  ///< spill()'s descriptor, without O_DIRECT (opened on first use)
    std::uint64_t spilled_bytes_ = 0;
    Stage stage_;               ///< being filled
    std::size_t used_ = 0;      ///< bytes staged
    std::uint64_t offset_ = 0;  ///< file offset of stage_[0] (a multiple of kStageBytes)
    std::size_t stages_ = 1;    ///< stages allocated

    std::mutex mutex_;
    std::condition_variable queued_;
    std::deque<Job> queue_;     ///< stages to write, in file order
    std::vector<Stage> spare_;  ///< written stages, for reuse
    bool stop_ = false;
    int error_ = 0;  ///< errno of the first failed write
    const char* error_what_ = "";
    std::thread writer_;  ///< started with the first full stage
};

}  // namespace beamtrace::detail
