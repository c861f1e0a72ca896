#include "beamtrace/core/communicator.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

namespace {

class PosixSharedFile final : public SharedFile {
  public:
    PosixSharedFile(std::filesystem::path path, bool create) : path_(std::move(path)) {
        fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC | (create ? O_CREAT | O_TRUNC : 0), 0644);
        if (fd_ < 0) {
            throw OutputError(path_.string() +
                              ": cannot open for writing: " + std::strerror(errno));
        }
    }
    ~PosixSharedFile() override {
        if (fd_ >= 0) {
            ::close(fd_);
        }
    }
    PosixSharedFile(const PosixSharedFile&) = delete;
    PosixSharedFile& operator=(const PosixSharedFile&) = delete;

    void write_at_all(std::uint64_t offset, std::span<const std::uint8_t> bytes) override {
        write_at(offset, bytes);
    }
    void write_at(std::uint64_t offset, std::span<const std::uint8_t> bytes) override {
        std::size_t done = 0;
        while (done < bytes.size()) {
            const ssize_t n = ::pwrite(fd_, bytes.data() + done, bytes.size() - done,
                                       static_cast<off_t>(offset + done));
            if (n < 0 && errno == EINTR) {
                continue;
            }
            if (n <= 0) {
                throw OutputError(path_.string() + ": write failed: " + std::strerror(errno));
            }
            done += static_cast<std::size_t>(n);
        }
    }
    void close() override {
        if (fd_ >= 0) {
            const int rc = ::close(fd_);
            fd_ = -1;
            if (rc != 0) {
                throw OutputError(path_.string() + ": close failed: " + std::strerror(errno));
            }
        }
    }

  private:
    std::filesystem::path path_;
    int fd_ = -1;
};

class SoloCommunicator final : public Communicator {
  public:
    [[nodiscard]] int rank() const override { return 0; }
    [[nodiscard]] int size() const override { return 1; }
    void sum(std::span<std::uint64_t> /*values*/) override {}
    void min(std::span<std::int64_t> /*values*/) override {}
    [[nodiscard]] std::uint64_t exclusive_sum(std::uint64_t /*value*/) override { return 0; }
    [[nodiscard]] std::string broadcast(const std::string& text, int /*root*/) override {
        return text;
    }
    [[nodiscard]] std::unique_ptr<SharedFile> open_shared(
        const std::filesystem::path& path) override {
        return open_posix_shared_file(path, true);
    }
};

}  // namespace

std::unique_ptr<Communicator> solo_communicator() {
    return std::make_unique<SoloCommunicator>();
}

std::unique_ptr<SharedFile> open_posix_shared_file(const std::filesystem::path& path, bool create) {
    return std::make_unique<PosixSharedFile>(path, create);
}

}  // namespace beamtrace
