#include "beamtrace/io/mapped_file.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& action, int error) {
    throw OutputError(path.string() + ": " + action + ": " + std::strerror(error));
}

}  // namespace

MappedFile::MappedFile(const std::filesystem::path& final_path, std::size_t size, bool buffered)
    : file_(final_path), size_(size) {
    fd_ = ::open(file_.temp_path().c_str(), O_RDWR | O_CLOEXEC);
    if (fd_ < 0) {
        fail(path(), "cannot open temporary file " + temp_path().string(), errno);
    }
    if (size_ == 0) {
        return;
    }
    // Reserve every block now: a full disk fails here, with a message, rather than as a SIGBUS
    // on the first store to a page the file system cannot place.
    if (const int error = ::posix_fallocate(fd_, 0, static_cast<off_t>(size_)); error != 0) {
        const std::string what = "cannot reserve " + std::to_string(size_) + " bytes";
        ::close(fd_);
        fd_ = -1;
        fail(path(), what, error);
    }
    void* map =
        buffered ? MAP_FAILED : ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
    if (map == MAP_FAILED) {  // e.g. a FUSE file system without shared mappings
        buffer_ = std::make_unique<char[]>(size_);  // zeros, as the file's
        map = buffer_.get();
    }
    data_ = static_cast<char*>(map);
}

MappedFile::~MappedFile() {
    unmap();
    if (fd_ >= 0) {
        ::close(fd_);
    }
    // file_'s destructor removes the temporary file unless committed.
}

void MappedFile::unmap() noexcept {
    if (data_ != nullptr && buffer_ == nullptr) {
        ::munmap(data_, size_);
    }
    data_ = nullptr;
    buffer_.reset();
}

void MappedFile::prefault(std::size_t offset, std::size_t length) const noexcept {
#ifdef MADV_POPULATE_WRITE
    if (!mapped() || data_ == nullptr || offset >= size_) {
        return;
    }
    const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
    const std::size_t begin = offset / page * page;
    const std::size_t end = std::min(size_, offset + length);
    // Errors (e.g. EINVAL before Linux 5.14) leave the pages to be faulted in one by one.
    (void)::madvise(data_ + begin, end - begin, MADV_POPULATE_WRITE);
#else
    (void)offset;
    (void)length;
#endif
}

void MappedFile::write_buffer() const {
    for (std::size_t done = 0; done < size_;) {
        const ssize_t n = ::pwrite(fd_, data_ + done, size_ - done, static_cast<off_t>(done));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            fail(path(), "write failed", n < 0 ? errno : EIO);
        }
        done += static_cast<std::size_t>(n);
    }
}

void MappedFile::commit() {
    if (fd_ < 0) {
        throw OutputError(path().string() + ": commit called twice");
    }
    if (buffer_ != nullptr) {
        write_buffer();
    }
    unmap();
    size_ = 0;
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) {
        fail(path(), "close failed", errno);
    }
    file_.commit();
}

}  // namespace beamtrace
