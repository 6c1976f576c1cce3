#include "parallel/petsc_engine.hpp"

#include "la/petsc.hpp"
#include "parallel/distributed_mesh.hpp"
#include "run/progress.hpp"

namespace vpc {

namespace {

/// Throws Interrupted on every rank if any has received a signal.
void stop_if_interrupted_anywhere(const la::Comm& comm) {
  if (const int s = static_cast<int>(comm.max(interrupt_signal()))) throw Interrupted(s);
}

}  // namespace

// Rank 0 builds the case and sends the mesh's dimension (or its error, which every
// rank then reports alike); the other ranks build everything else (laws and
// formulas are C++ objects made by the parser) around an empty mesh of that dimension.
Case load_case_everywhere(const CaseLoader& load, const la::Comm& comm) {
  Case c;
  double dim = 0;
  la::on_root(comm, [&] {
    c = load({});
    dim = c.problem->mesh.dim();
  });
  dim = la::broadcast(comm, std::vector<double>{dim})[0];
  if (comm.rank() != 0) {
    MeshRequest without_mesh;  // the mesh comes from rank 0 (distribute_mesh)
    without_mesh.build = false;
    without_mesh.dim = static_cast<int>(dim);
    c = load(without_mesh);
  }
  return c;
}

namespace {

std::unique_ptr<TimeStepper> distributed_stepper(MPI_Comm mpi_comm, std::shared_ptr<const Problem> problem,
                                                 const SolverChoice& choice, const std::string& linear_solver) {
  MeshPart part = distribute_mesh(mpi_comm, *problem);
  PetscSolverOptions linear;
  linear.kind = linear_solver;
  // Iterative solves stop 100x under the relative residual a step accepts (solver.tolerance,
  // 1e-8): tighter only costs iterations (at 1e-12, a third more on foundation-3d).
  linear.rtol = 1e-2 * choice.residual_tolerance;
  return std::make_unique<TimeStepper>(std::move(problem), std::move(part),
                                       la::make_petsc_backend(la::make_mpi_comm(mpi_comm), linear), choice);
}

}  // namespace

std::unique_ptr<TimeStepper> petsc_stepper(MPI_Comm mpi_comm, Case& c, const std::string& linear_solver) {
  auto stepper = distributed_stepper(mpi_comm, c.problem, c.solvers, linear_solver);
  c.problem->mesh = Mesh();  // from here on, rank 0 too holds its part only
  return stepper;
}

EngineChoice petsc_engine(MPI_Comm comm, const std::string& linear_solver) {
  return {[comm, linear_solver](const CaseLoader& load, const RunOptions& o) {
            RunOptions with = o;  // the engine's solver (the command line's fallback may differ from --linear-solver)
            with.linear_solver = linear_solver;
            return set_up_petsc(comm, load, with);
          },
          [comm, linear_solver](std::shared_ptr<const Problem> problem, const SolverChoice& choice) {
            return distributed_stepper(comm, std::move(problem), choice, linear_solver);
          },
          la::make_mpi_comm(comm).rank() == 0};
}

std::unique_ptr<Engine> set_up_petsc(MPI_Comm mpi_comm, const CaseLoader& load, const RunOptions& o) {
  const la::Comm comm = la::make_mpi_comm(mpi_comm);
  la::on_root(comm, [&] { begin_run(o); });
  Case c = load_case_everywhere(load, comm);
  c.solvers.max_halvings = o.halvings;
  stop_if_interrupted_anywhere(comm);
  // Collective stages: a signal is looked at after them all.
  c.solvers.on_setup_stage = StageLog(o.quiet || comm.rank() != 0);
  auto stepper = petsc_stepper(mpi_comm, c, o.linear_solver);
  stop_if_interrupted_anywhere(comm);
  return make_engine(std::move(c), std::move(stepper), o.quiet);
}

}  // namespace vpc
