#pragma once
// The seconds this process spent starting MPI and PETSc (app/parallel_run.cpp), a fact of the
// process: summary.json reports them apart (timing_seconds.mpi_start, within "wall"), so that a
// run under mpirun compares with one process on the work both do (docs/parallel.md, "Two ranks
// against one process"). 0 where MPI was not started.

namespace vpc {

inline double& mpi_start_seconds() {
  static double seconds = 0;
  return seconds;
}

}  // namespace vpc
