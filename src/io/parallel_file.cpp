#include "beamtrace/io/parallel_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

ParallelFile::ParallelFile(const std::filesystem::path& final_path, std::uint64_t reserve_bytes)
    : file_(final_path), fd_(::fileno(file_.stream())) {
    if (reserve_bytes == 0) {
        return;
    }
    if (const int error = ::posix_fallocate(fd_, 0, static_cast<off_t>(reserve_bytes));
        error != 0) {
        throw OutputError(path().string() + ": cannot reserve " + std::to_string(reserve_bytes) +
                          " bytes: " + std::strerror(error));
    }
}

void ParallelFile::write_at(std::string_view bytes, std::uint64_t offset) const {
    while (!bytes.empty()) {
        const ssize_t n = ::pwrite(fd_, bytes.data(), bytes.size(), static_cast<off_t>(offset));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            throw OutputError(path().string() +
                              ": write failed: " + std::strerror(n < 0 ? errno : EIO));
        }
        bytes.remove_prefix(static_cast<std::size_t>(n));
        offset += static_cast<std::uint64_t>(n);
    }
}

StagedRange::StagedRange(const ParallelFile& file, std::uint64_t offset)
    : file_(file),
      offset_(offset),
      buffer_(std::make_unique_for_overwrite<char[]>(kBlock + kSlack)) {}

char* StagedRange::flush(char* at) {
    char* const end = limit();
    if (at < end) {
        return at;
    }
    const auto block = static_cast<std::size_t>(end - begin());
    file_.write_at({begin(), block}, offset_);
    offset_ += block;
    const auto past = static_cast<std::size_t>(at - end);
    std::memmove(begin(), end, past);
    return begin() + past;
}

void StagedRange::finish(const char* at) {
    file_.write_at({begin(), static_cast<std::size_t>(at - begin())}, offset_);
}

}  // namespace beamtrace
