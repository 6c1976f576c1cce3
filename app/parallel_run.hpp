#pragma once
// `vpcontact run` and `check` on the distributed engine (PETSc + MPI; docs/parallel.md):
//   mpirun -np P vpcontact run CASE [options]
// In a build with VPCONTACT_ENABLE_PETSC, a run started by mpirun/mpiexec (any
// -np, 1 included) uses it; --engine serial|petsc forces one. This header also
// compiles without PETSc, where it explains what is missing.
#include "core/error.hpp"
#include "run/run_case.hpp"

#include <cstdlib>
#include <functional>
#include <string>

namespace vpc {

/// The number of processes of the MPI job this process was started in, 0 if none.
inline int mpi_launch_size() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* v = std::getenv(var)) return std::atoi(v);
  return 0;
}

/// Whether `run` takes the PETSc engine: --engine petsc, or auto (the default)
/// under mpirun. Throws vpc::Error for a choice this build cannot honour.
inline bool use_petsc_engine(const std::string& engine) {
  require(engine == "auto" || engine == "serial" || engine == "petsc",
          "--engine must be auto, serial or petsc (got '{}')", engine);
  const int launched = mpi_launch_size();
#ifdef VPCONTACT_WITH_PETSC
  if (engine == "petsc") return true;
  if (engine == "serial") {
    require(launched <= 1, "--engine serial under mpirun with {} processes: each would run the whole case; "
                           "use -np 1, or the PETSc engine", launched);
    return false;
  }
  return launched >= 1;
#else
  require(engine != "petsc", "--engine petsc: this vpcontact was built without PETSc; configure it with "
                             "-DVPCONTACT_ENABLE_PETSC=ON (docs/parallel.md)");
  require(launched <= 1, "started by mpirun with {} processes, but this vpcontact was built without PETSc: each "
                         "process would run the whole case; build with -DVPCONTACT_ENABLE_PETSC=ON (docs/parallel.md)",
          launched);
  return false;
#endif
}

/// What a command does with an engine (run/run_case.hpp): run it, check the set-up, or
/// make the steppers of a convergence study.
using EngineTask = std::function<int(const EngineChoice&)>;

#ifdef VPCONTACT_WITH_PETSC
/// Calls `task` with the PETSc engine on every rank of MPI_COMM_WORLD (PETSc
/// initialized, one thread per rank); returns the exit code. An error every rank
/// meets alike is reported once; any other stops every rank (MPI_Abort).
int parallel_run(const RunOptions& options, const EngineTask& task);
/// Calls `task` with --engine auto's engine on this one process (parallel/petsc_engine.hpp
/// auto_engine): PETSc is initialized only if the solver plan takes CG + GAMG.
int auto_run(const EngineTask& task);
#else
inline int parallel_run(const RunOptions&, const EngineTask&) {
  fail("this vpcontact was built without PETSc (docs/parallel.md)");
}
#endif

}  // namespace vpc
