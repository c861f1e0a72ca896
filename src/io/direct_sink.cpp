#include "io/detail/direct_sink.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace::detail {
namespace {

constexpr std::size_t kAlign = 4096;  // covers every logical block size
static_assert(DirectSink::kStageBytes % kAlign == 0);

char* allocate_stage() {
    return static_cast<char*>(std::aligned_alloc(kAlign, DirectSink::kStageBytes));
}

/// Writes `size` bytes at `offset`; 0, or the errno of the failure.
int write_all(int fd, const char* data, std::size_t size, std::uint64_t offset) {
    std::size_t done = 0;
    while (done < size) {
        const ssize_t n = ::pwrite(fd, data + done, size - done, static_cast<off_t>(offset + done));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return n < 0 ? errno : EIO;
        }
        done += static_cast<std::size_t>(n);
    }
    return 0;
}

}  // namespace

void DirectSink::Free::operator()(char* p) const {
    std::free(p);
}

DirectSink::DirectSink(const std::filesystem::path& path, std::filesystem::path display,
                       std::function<void()> before_write)
    : path_(path), display_(std::move(display)), before_write_(std::move(before_write)) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | O_DIRECT);
    if (fd_ < 0) {  // EINVAL: the file system has no direct I/O
        fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    }
    if (fd_ < 0) {
        fail("cannot open for writing", errno);
    }
    // What the kernel says the descriptor does, not what was asked of it.
    const int flags = ::fcntl(fd_, F_GETFL);
    direct_ = flags >= 0 && (flags & O_DIRECT) != 0;
    stage_.reset(allocate_stage());
    if (!stage_) {
        ::close(fd_);
        throw OutputError(display_.string() + ": out of memory for the write buffer");
    }
}

DirectSink::~DirectSink() {
    {
        const std::lock_guard lock(mutex_);
        queue_.clear();  // not finished: an abandoned file, nothing more to write
        stop_ = true;
    }
    queued_.notify_all();
    if (writer_.joinable()) {
        writer_.join();
    }
    for (const int fd : {fd_, buffered_fd_}) {
        if (fd >= 0) {
            ::close(fd);
        }
    }
}

void DirectSink::fail(const char* what, int error_number) const {
    throw OutputError(display_.string() + ": " + what + ": " + std::strerror(error_number));
}

void DirectSink::check_error() {
    if (error_ != 0) {
        fail(error_what_, error_);
    }
}

bool DirectSink::write_stage(const char* data, std::uint64_t offset) {
    int error = write_all(fd_, data, kStageBytes, offset);
    if (error == EINVAL && direct_) {
        // Direct I/O refused after all (alignment the device does not take): go through the
        // page cache from here on.
        ::close(fd_);
        direct_ = false;
        fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
        if (fd_ < 0) {
            error_what_ = "cannot reopen for writing";
            return false;
        }
        error = write_all(fd_, data, kStageBytes, offset);
    }
    if (error != 0) {
        error_what_ = "write failed";
        errno = error;
        return false;
    }
    direct_bytes_ += direct_ ? kStageBytes : 0;
    return true;
}

void DirectSink::spill(const char* data, std::uint64_t offset) {
    if (buffered_fd_ < 0) {
        buffered_fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
        if (buffered_fd_ < 0) {
            fail("cannot open for writing", errno);
        }
    }
    if (const int error = write_all(buffered_fd_, data, kStageBytes, offset); error != 0) {
        fail("write failed", error);
    }
    spilled_bytes_ += kStageBytes;
}

void DirectSink::run_writes() {
    std::unique_lock lock(mutex_);
    for (;;) {
        queued_.wait(lock, [&] { return stop_ || !queue_.empty(); });
        if (queue_.empty()) {
            return;  // stopped, and nothing is queued
        }
        Job job = std::move(queue_.front());
        queue_.pop_front();
        const bool skip = error_ != 0;  // after an error the file is lost anyway
        lock.unlock();
        if (before_write_) {
            before_write_();
        }
        const bool ok = skip || write_stage(job.stage.get(), job.offset);
        const int error_number = errno;
        lock.lock();
        if (!ok) {
            error_ = error_number != 0 ? error_number : EIO;
        }
        spare_.push_back(std::move(job.stage));
    }
}

void DirectSink::submit() {
    std::unique_lock lock(mutex_);
    check_error();
    Stage next;
    if (!spare_.empty()) {
        next = std::move(spare_.back());
        spare_.pop_back();
    } else if (stages_ == kStages) {
        // Every stage is queued or being written: the disk is behind. This one goes through the
        // page cache now, and is filled again.
        lock.unlock();
        spill(stage_.get(), offset_);
        offset_ += kStageBytes;
        used_ = 0;
        return;
    }
    queue_.push_back({std::move(stage_), offset_});
    offset_ += kStageBytes;
    used_ = 0;
    if (!writer_.joinable()) {
        writer_ = std::thread([this] { run_writes(); });
    } else {
        queued_.notify_one();
    }
    if (!next) {
        ++stages_;
        lock.unlock();
        next.reset(allocate_stage());
        if (!next) {
            throw OutputError(display_.string() + ": out of memory for the write buffer");
        }
    }
    stage_ = std::move(next);
}

void DirectSink::append(const void* data, std::size_t size) {
    const auto* p = static_cast<const char*>(data);
    while (size > 0) {
        const std::size_t n = std::min(size, kStageBytes - used_);
        std::memcpy(stage_.get() + used_, p, n);
        used_ += n;
        p += n;
        size -= n;
        if (used_ == kStageBytes) {
            submit();
        }
    }
}

void DirectSink::stop_writes() {
    std::deque<Job> queued;
    {
        const std::lock_guard lock(mutex_);
        queued.swap(queue_);
        stop_ = true;
    }
    queued_.notify_all();
    // The disk is behind by these: the page cache takes them now, beside the one in flight.
    std::exception_ptr spill_error;
    try {
        for (const Job& job : queued) {
            spill(job.stage.get(), job.offset);
        }
    } catch (...) {
        spill_error = std::current_exception();
    }
    if (writer_.joinable()) {
        writer_.join();
    }
    check_error();  // the earlier error first: it is what went wrong first
    if (spill_error) {
        std::rethrow_exception(spill_error);
    }
}

void DirectSink::finish(std::FILE* stream) {
    stop_writes();
    if (::fseeko(stream, static_cast<off_t>(offset_), SEEK_SET) != 0) {
        fail("cannot seek", errno);
    }
    if (used_ > 0 && std::fwrite(stage_.get(), 1, used_, stream) != used_) {
        fail("write failed", errno);
    }
    offset_ += used_;
    used_ = 0;
    ::close(fd_);
    fd_ = -1;
}

}  // namespace beamtrace::detail
