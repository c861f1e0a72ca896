#include "io/detail/direct_sink.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace::detail {
namespace {

constexpr std::size_t kAlign = 4096;                       // covers every logical block size
constexpr std::size_t kStageBytes = std::size_t{8} << 20;  // a multiple of kAlign

}  // namespace

void DirectSink::Free::operator()(char* p) const {
    std::free(p);
}

DirectSink::DirectSink(const std::filesystem::path& path, std::filesystem::path display)
    : path_(path), display_(std::move(display)) {
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
    stage_.reset(static_cast<char*>(std::aligned_alloc(kAlign, kStageBytes)));
    if (!stage_) {
        ::close(fd_);
        throw OutputError(display_.string() + ": out of memory for the write buffer");
    }
}

DirectSink::~DirectSink() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

void DirectSink::fail(const char* what, int error_number) const {
    throw OutputError(display_.string() + ": " + what + ": " + std::strerror(error_number));
}

void DirectSink::write_aligned(std::size_t bytes) {
    std::size_t done = 0;
    while (done < bytes) {
        const ssize_t n =
            ::pwrite(fd_, stage_.get() + done, bytes - done, static_cast<off_t>(offset_ + done));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n < 0 && errno == EINVAL && direct_) {
            // Direct I/O refused after all (alignment the device does not take): go through
            // the page cache from here on.
            ::close(fd_);
            direct_ = false;
            fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
            if (fd_ < 0) {
                fail("cannot reopen for writing", errno);
            }
            continue;
        }
        if (n <= 0) {
            fail("write failed", n < 0 ? errno : EIO);
        }
        done += static_cast<std::size_t>(n);
        direct_bytes_ += direct_ ? static_cast<std::uint64_t>(n) : 0;
    }
    // Keep the unaligned rest at the front of the stage.
    std::memmove(stage_.get(), stage_.get() + bytes, used_ - bytes);
    used_ -= bytes;
    offset_ += bytes;
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
            write_aligned(kStageBytes);
        }
    }
}

void DirectSink::finish(std::FILE* stream) {
    write_aligned(used_ / kAlign * kAlign);
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
