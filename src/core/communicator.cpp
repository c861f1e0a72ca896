#include "beamtrace/core/communicator.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <limits>

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
    [[nodiscard]] std::vector<std::uint64_t> all_gather(std::uint64_t value) override {
        return {value};
    }
    [[nodiscard]] std::string broadcast(const std::string& text, int /*root*/) override {
        return text;
    }
    [[nodiscard]] std::unique_ptr<SharedFile> open_shared(
        const std::filesystem::path& path) override {
        return open_posix_shared_file(path, true);
    }
};

}  // namespace

void agree_on_error(Communicator& comm, const std::exception_ptr& error) {
    std::int64_t first = error ? comm.rank() : std::numeric_limits<std::int64_t>::max();
    comm.min({&first, 1});
    if (first == std::numeric_limits<std::int64_t>::max()) {
        return;
    }
    // The kind (c config, i input, x interrupted, o other) and the message of that rank.
    std::string said;
    if (error) {
        try {
            std::rethrow_exception(error);
        } catch (const ConfigError& e) {
            said = std::string("c") + e.what();
        } catch (const InputError& e) {
            said = std::string("i") + e.what();
        } catch (const Interrupted& e) {
            said = "x" + std::to_string(e.reason());
        } catch (const std::exception& e) {
            said = std::string("o") + e.what();
        } catch (...) {
            said = "ounknown error";
        }
    }
    said = comm.broadcast(said, static_cast<int>(first));
    if (error) {
        std::rethrow_exception(error);
    }
    const std::string text = said.substr(1);
    switch (said.empty() ? 'o' : said[0]) {
        case 'c':
            throw ConfigError(text);
        case 'i':
            throw InputError("rank " + std::to_string(first), text);
        case 'x':
            throw Interrupted("survey", std::stoi(text));
        default:
            throw OutputError("rank " + std::to_string(first) + ": " + text);
    }
}

std::unique_ptr<Communicator> solo_communicator() {
    return std::make_unique<SoloCommunicator>();
}

std::unique_ptr<SharedFile> open_posix_shared_file(const std::filesystem::path& path, bool create) {
    return std::make_unique<PosixSharedFile>(path, create);
}

}  // namespace beamtrace
