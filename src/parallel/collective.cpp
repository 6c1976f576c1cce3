#include "parallel/collective.hpp"

#include "la/petsc.hpp"

namespace vpc {

// One rule for errors in collective work: la::Comm's (the lowest failing rank's message).
void throw_if_failed_anywhere(MPI_Comm comm, bool failed, std::string message) {
  la::make_mpi_comm(comm).throw_if_any(failed, message);
}

}  // namespace vpc
