// start_mpi() of a build without MPI: always one process.
#include "mpi_world.hpp"

namespace beamtrace::cli {

std::unique_ptr<MpiWorld> start_mpi(int& /*argc*/, char**& /*argv*/) {
    return nullptr;
}

}  // namespace beamtrace::cli
