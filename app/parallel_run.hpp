#pragma once
// `vpcontact run` on the distributed engine (PETSc + MPI; docs/parallel.md):
//   mpirun -np P vpcontact run CASE [options]
// In a build with VPCONTACT_ENABLE_PETSC, a run started by mpirun/mpiexec (any
// -np, 1 included) uses it; --engine serial|petsc forces one. This header also
// compiles without PETSc, where it explains what is missing.
#include "io/case.hpp"
#include "core/error.hpp"
#include "figures.hpp"

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace vpc {

struct ParallelRunOptions {
  bool quiet = false;
  std::string resume;
  int halvings = 0;
  std::string linear_solver = "mumps";  // mumps, cg-gamg, cg-hypre
  bool plot = false;
  int checkpoint_every = -1;        // steps; -1: by wall time
  double checkpoint_seconds = 60;   // without checkpoint_every
  std::string header;                       // "vpcontact: NAME — description", printed first by rank 0
  std::filesystem::path output_directory;   // checked by rank 0 before any set-up
  std::vector<std::string> argv;            // the command line, for the --resume command after a signal
  PlotOptions plot_options;
};

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

/// Builds the case; rank 0 with its mesh, the other ranks without (MeshRequest).
using CaseLoader = std::function<Case(const MeshRequest&)>;

#ifdef VPCONTACT_WITH_PETSC
/// Runs the case on every rank of MPI_COMM_WORLD; returns the exit code. Only
/// rank 0 builds (reads, generates) the whole mesh; it sends each rank its part.
int parallel_run(const CaseLoader& load, const ParallelRunOptions& options);
#else
inline int parallel_run(const CaseLoader&, const ParallelRunOptions&) {
  fail("this vpcontact was built without PETSc (docs/parallel.md)");
}
#endif

}  // namespace vpc
