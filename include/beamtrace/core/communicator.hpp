// The collective operations a survey run by many processes needs (run_survey_distributed),
// behind one small interface: MPI in the CLI (apps/beamtrace/mpi_communicator.cpp), one process
// here (solo_communicator), threads of one process in the tests. Every call is collective:
// every rank makes the same calls in the same order.
#pragma once

#include <cstdint>
#include <exception>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace beamtrace {

/// A file every rank writes parts of.
class SharedFile {
  public:
    virtual ~SharedFile() = default;
    /// This rank alone writes `bytes` at `offset`.
    virtual void write_at(std::uint64_t offset, std::span<const std::uint8_t> bytes) = 0;
    /// Collective: flushes and closes the file. Throws OutputError naming it on failure.
    virtual void close() = 0;
};

class Communicator {
  public:
    virtual ~Communicator() = default;
    [[nodiscard]] virtual int rank() const = 0;
    [[nodiscard]] virtual int size() const = 0;
    /// Element-wise sum over the ranks, in place: every rank gets the result.
    virtual void sum(std::span<std::uint64_t> values) = 0;
    /// Element-wise minimum over the ranks, in place (the maximum: negate).
    virtual void min(std::span<std::int64_t> values) = 0;
    /// Every rank's `value`, by rank, on every rank.
    [[nodiscard]] virtual std::vector<std::uint64_t> all_gather(std::uint64_t value) = 0;
    /// Rank `root`'s `text` on every rank.
    [[nodiscard]] virtual std::string broadcast(const std::string& text, int root) = 0;
    /// Collective: `path` created (truncated) for writing by every rank. Throws OutputError
    /// naming the file on any rank that cannot open it.
    [[nodiscard]] virtual std::unique_ptr<SharedFile> open_shared(
        const std::filesystem::path& path) = 0;
};

/// Collective: returns when no rank has an error (`error` null on every rank). Otherwise every
/// rank throws: a rank with its own error rethrows it, the others an error of the same kind
/// (ConfigError, InputError, Interrupted; OutputError for any other) with the message of the
/// lowest failing rank, so that rank 0 alone can report it.
void agree_on_error(Communicator& comm, const std::exception_ptr& error);

/// The communicator of a process on its own: rank 0 of 1.
[[nodiscard]] std::unique_ptr<Communicator> solo_communicator();

/// A SharedFile of POSIX writes (pwrite) to `path`; `create` truncates or creates it, else it
/// must exist. Throws
/// OutputError naming the file.
[[nodiscard]] std::unique_ptr<SharedFile> open_posix_shared_file(const std::filesystem::path& path,
                                                                 bool create);

}  // namespace beamtrace
