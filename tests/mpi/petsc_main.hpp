#pragma once
// The main() of an MPI test program: PETSc started and finished around `run`, and an
// error on one rank reported with the rank and turned into MPI_Abort, so that no other
// rank is left waiting in a collective.
#include "la/petsc_util.hpp"

#include <fmt/format.h>
#include <petscsys.h>

#include <exception>

namespace vpc::test {

template <typename Run>
int petsc_main(int argc, char** argv, const char* program, Run&& run) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr)) return 3;
  int rc = 0;
  try {
    rc = run(argc, argv);
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}: rank {}: error: {}\n", program, vpc::comm_rank(PETSC_COMM_WORLD), e.what());
    MPI_Abort(PETSC_COMM_WORLD, 1);
  }
  PetscFinalize();
  return rc;
}

}  // namespace vpc::test
