// MPI for the CLI: `mpirun -n N beamtrace survey ...` runs one survey on N ranks
// (run_survey_distributed over an MPI communicator). Without MPI in the build, or when not
// launched by mpirun, start_mpi() returns null and everything runs as one process.
#pragma once

#include <memory>

#include "beamtrace/core/communicator.hpp"

namespace beamtrace::cli {

/// MPI initialised for this process (MPI_THREAD_FUNNELED: only the main thread calls MPI);
/// finalised when destroyed.
class MpiWorld {
  public:
    virtual ~MpiWorld() = default;
    /// MPI_COMM_WORLD (errors returned and thrown as OutputError, not fatal).
    [[nodiscard]] virtual Communicator& comm() = 0;
};

/// The MPI world when this process was started by mpirun/srun (an MPI launcher's environment)
/// and beamtrace was built with MPI; else null.
[[nodiscard]] std::unique_ptr<MpiWorld> start_mpi(int& argc, char**& argv);

}  // namespace beamtrace::cli
