// start_mpi() with MPI: MPI_COMM_WORLD as a beamtrace::Communicator, MPI-IO for the shared file.
#include <mpi.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "beamtrace/core/error.hpp"
#include "mpi_world.hpp"

namespace beamtrace::cli {

namespace {

/// Throws OutputError with MPI's text for a failed call.
void check(int code, const std::string& what) {
    if (code == MPI_SUCCESS) {
        return;
    }
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw OutputError(what + ": " + std::string(text, static_cast<std::size_t>(length)));
}

/// Bytes per MPI call (counts are int).
constexpr std::size_t kPiece = std::size_t{1} << 30;

class MpiFile final : public SharedFile {
  public:
    MpiFile(MPI_Comm comm, const std::filesystem::path& path) : path_(path) {
        check(MPI_File_open(comm, path.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY, MPI_INFO_NULL,
                            &file_),
              path.string() + ": cannot open for writing");
        check(MPI_File_set_errhandler(file_, MPI_ERRORS_RETURN), path.string());
        check(MPI_File_set_size(file_, 0), path.string() + ": cannot truncate");
    }
    ~MpiFile() override {
        if (file_ != MPI_FILE_NULL) {
            MPI_File_close(&file_);
        }
    }
    MpiFile(const MpiFile&) = delete;
    MpiFile& operator=(const MpiFile&) = delete;

    void write_at(std::uint64_t offset, std::span<const std::uint8_t> bytes) override {
        for (std::size_t from = 0; from < bytes.size(); from += kPiece) {
            const std::size_t size = std::min(kPiece, bytes.size() - from);
            MPI_Status status;
            check(MPI_File_write_at(file_, static_cast<MPI_Offset>(offset + from),
                                    bytes.data() + from, static_cast<int>(size), MPI_BYTE, &status),
                  path_.string() + ": write failed");
        }
    }
    void close() override { check(MPI_File_close(&file_), path_.string() + ": close failed"); }

  private:
    std::filesystem::path path_;
    MPI_File file_ = MPI_FILE_NULL;
};

class MpiCommunicator final : public Communicator {
  public:
    MpiCommunicator() {
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
    [[nodiscard]] int rank() const override { return rank_; }
    [[nodiscard]] int size() const override { return size_; }
    void sum(std::span<std::uint64_t> values) override {
        check(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()),
                            MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD),
              "MPI sum");
    }
    void min(std::span<std::int64_t> values) override {
        check(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()),
                            MPI_INT64_T, MPI_MIN, MPI_COMM_WORLD),
              "MPI min");
    }
    [[nodiscard]] std::vector<std::uint64_t> all_gather(std::uint64_t value) override {
        std::vector<std::uint64_t> out(static_cast<std::size_t>(size_));
        check(MPI_Allgather(&value, 1, MPI_UINT64_T, out.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD),
              "MPI gather");
        return out;
    }
    [[nodiscard]] std::string broadcast(const std::string& text, int root) override {
        unsigned long long size = text.size();
        check(MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, root, MPI_COMM_WORLD), "MPI broadcast");
        std::string out = rank_ == root ? text : std::string(size, '\0');
        check(MPI_Bcast(out.data(), static_cast<int>(size), MPI_CHAR, root, MPI_COMM_WORLD),
              "MPI broadcast");
        return out;
    }
    [[nodiscard]] std::unique_ptr<SharedFile> open_shared(
        const std::filesystem::path& path) override {
        return std::make_unique<MpiFile>(MPI_COMM_WORLD, path);
    }

  private:
    int rank_ = 0, size_ = 1;
};

class MpiSession final : public MpiWorld {
  public:
    MpiSession(int& argc, char**& argv) {
        int provided = 0;
        MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
        MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
        comm_ = std::make_unique<MpiCommunicator>();
    }
    ~MpiSession() override {
        comm_.reset();
        MPI_Finalize();
    }
    MpiSession(const MpiSession&) = delete;
    MpiSession& operator=(const MpiSession&) = delete;
    [[nodiscard]] Communicator& comm() override { return *comm_; }

  private:
    std::unique_ptr<MpiCommunicator> comm_;
};

/// Whether an MPI launcher (Open MPI's mpirun, MPICH's hydra, Slurm's srun) started us.
bool launched_by_mpi() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "PMI_RANK"}) {
        if (std::getenv(name) != nullptr) {
            return true;
        }
    }
    return false;
}

}  // namespace

std::unique_ptr<MpiWorld> start_mpi(int& argc, char**& argv) {
    if (!launched_by_mpi()) {
        return nullptr;
    }
    return std::make_unique<MpiSession>(argc, argv);
}

}  // namespace beamtrace::cli
