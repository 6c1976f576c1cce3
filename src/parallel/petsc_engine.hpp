#pragma once
// The run loop's engine (run/engine.hpp, make_run) on the ranks of an MPI
// communicator, over the PETSc backend (docs/parallel.md). Only rank 0 builds
// (reads, generates) the whole mesh; it sends each rank its part.
#include "la/comm.hpp"
#include "la/petsc.hpp"
#include "run/run_case.hpp"

#include <mpi.h>

#include <functional>

namespace vpc {

/// The case on every rank, its mesh on rank 0 only (for distribute_mesh). Collective.
Case load_case_everywhere(const CaseLoader& load, const la::Comm& comm);

/// The stepper of `c` (loaded by load_case_everywhere) on this rank's part of its
/// mesh, over the PETSc backend with `linear`'s solver (its tolerance: the case's); frees rank
/// 0's whole mesh. Collective.
std::unique_ptr<TimeStepper> petsc_stepper(MPI_Comm comm, Case& c, PetscSolverOptions linear);

/// set_up_serial on the ranks of `comm`: the case on every rank, the mesh
/// distributed, the PETSc backend. Collective.
std::unique_ptr<Run> set_up_petsc(MPI_Comm comm, const CaseLoader& load, const RunOptions& options);

/// --engine auto on one process: the case loaded, then the solver plan (run/solver_plan.hpp)
/// takes CHOLMOD (set_up_on_one_process) or CG + GAMG on the PETSc engine on the communicator
/// `start_petsc` returns (PETSc is initialized only then).
EngineChoice auto_engine(const std::function<MPI_Comm()>& start_petsc);

/// The engine on the ranks of `comm`: set_up_petsc, and steppers over the PETSc backend
/// with `linear_solver` on each problem's mesh (rank 0's, distributed and kept).
EngineChoice petsc_engine(MPI_Comm comm, const std::string& linear_solver);

}  // namespace vpc
