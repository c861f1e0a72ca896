#include "beamtrace/core/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

namespace {

constexpr std::size_t kBufferBytes = std::size_t{1} << 20;
constexpr int kMaxNameAttempts = 100;

/// `.<name>.<pid>.tmp` for attempt 0, `.<name>.<pid>-<k>.tmp` after that.
std::filesystem::path temp_name(const std::filesystem::path& final_path, int attempt) {
    std::string name = "." + final_path.filename().string() + "." + std::to_string(::getpid());
    if (attempt > 0) {
        name += "-" + std::to_string(attempt);
    }
    name += ".tmp";
    return final_path.parent_path() / name;
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path final_path, bool fsync_on_commit)
    : final_path_(std::move(final_path)), fsync_on_commit_(fsync_on_commit) {
    if (final_path_.filename().empty()) {
        throw OutputError(final_path_.string() + ": not a file name");
    }
    // O_EXCL: never share a temporary file with another writer of the same output (another
    // AtomicFile in this process, or a stale file left by a crashed process with the same pid).
    int fd = -1;
    for (int attempt = 0; attempt < kMaxNameAttempts; ++attempt) {
        temp_path_ = temp_name(final_path_, attempt);
        fd = ::open(temp_path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST) {
            break;
        }
    }
    if (fd < 0) {
        fail("cannot create temporary file " + temp_path_.string(), errno);
    }
    file_ = ::fdopen(fd, "wb");
    if (file_ == nullptr) {
        const int error_number = errno;
        ::close(fd);
        std::error_code ignored;
        std::filesystem::remove(temp_path_, ignored);
        fail("cannot open stream", error_number);
    }
    buffer_ = std::make_unique_for_overwrite<char[]>(kBufferBytes);  // touched only if used
    std::setvbuf(file_, buffer_.get(), _IOFBF, kBufferBytes);
}

AtomicFile::~AtomicFile() {
    if (file_ != nullptr) {
        std::fclose(file_);
    }
    if (!committed_) {
        std::error_code ignored;
        std::filesystem::remove(temp_path_, ignored);
    }
}

void AtomicFile::write(const void* data, std::size_t size) {
    if (file_ == nullptr) {
        throw OutputError(final_path_.string() + ": write after commit");
    }
    if (size == 0) {
        return;
    }
    if (std::fwrite(data, 1, size, file_) != size) {
        fail("write failed", errno);
    }
}

void AtomicFile::commit() {
    if (file_ == nullptr) {
        throw OutputError(final_path_.string() + ": commit called twice");
    }
    if (std::fflush(file_) != 0) {
        fail("write failed", errno);
    }
    if (std::ferror(file_) != 0) {
        // A write through stream() failed earlier; errno may no longer say why.
        fail("an earlier write failed", EIO);
    }
    if (fsync_on_commit_ && ::fsync(::fileno(file_)) != 0) {
        fail("fsync failed", errno);
    }
    std::FILE* file = file_;
    file_ = nullptr;
    if (std::fclose(file) != 0) {
        fail("close failed", errno);
    }
    if (std::rename(temp_path_.c_str(), final_path_.c_str()) != 0) {
        fail("cannot rename " + temp_path_.string() + " onto it", errno);
    }
    committed_ = true;
}

void AtomicFile::fail(std::string_view action, int error_number) const {
    throw OutputError(final_path_.string() + ": " + std::string(action) + ": " +
                      std::strerror(error_number));
}

}  // namespace beamtrace
