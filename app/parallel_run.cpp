#include "parallel_run.hpp"

#include "parallel/distributed_time_stepper.hpp"
#include "parallel/parallel_output.hpp"
#include "progress.hpp"
#include "solvers/blas_threads.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace vpc {

namespace {

void describe(const Case& c, const DistributedTimeStepper& stepper, int size, const std::string& linear) {
  const auto& p = stepper.problem();
  const auto& part = stepper.part();
  fmt::print("vpcontact: {} — {}\n", c.name, c.description);
  fmt::print("  PETSc engine on {} MPI rank{}: linear solver {}{}\n", size, size > 1 ? "s" : "", linear,
             stepper.keeps_w() ? "" : " (K^-1 N^T not kept: two solves per step)");
  fmt::print("  mesh: d = {}, {} nodes, {} cells; {} free displacement dofs, {} contact nodes\n", part.mesh.dim(),
             part.n_global_nodes, part.n_global_cells, part.n_global_dofs, part.n_contact);
  fmt::print("  Γ1 (clamped): {}; Γ3 (contact): {}\n", fmt::join(p.clamped, ", "), fmt::join(p.contact.parts, ", "));
  fmt::print("  elasticity: {} (E = {}, nu = {}); G: {}; phi: {}\n", p.elasticity.name(), p.elasticity.young(),
             p.elasticity.poisson(), p.law->describe(), p.source->describe());
  fmt::print("  kappa = {}; T = {}, k = {}, N = {}; solvers: contact {}, damage {}; setup {:.3f} s\n", p.kappa,
             p.final_time, p.step(), p.n_steps, c.solvers.contact, c.solvers.damage, stepper.setup_timing().total);
  std::fflush(stdout);
}

int run(Case& c, const ParallelRunOptions& o, MPI_Comm comm) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const int rank = comm_rank(comm), size = comm_size(comm);
  PetscSolverOptions linear;
  linear.kind = o.linear_solver;

  DistributedMesh part = distribute_mesh(comm, *c.problem);
  c.problem->mesh = Mesh();  // from here on, every rank holds its part only
  DistributedTimeStepper stepper(c.problem, std::move(part), c.solvers, linear);
  if (!o.quiet && rank == 0) describe(c, stepper, size, linear.kind);
  ParallelOutput output(stepper, c.output, linear.kind);
  output.start();
  Progress progress(c.problem->n_steps, o.quiet || rank != 0);
  while (!stepper.done()) {
    const StepReport r = stepper.step();  // the same report on every rank
    if (!r.ok) {
      progress.finish();
      output.finish(std::chrono::duration<double>(Clock::now() - t0).count());
      if (rank == 0)
        fmt::print(stderr,
                   "vpcontact: error: step {} (t = {}) failed: contact solver {} after {} iterations (residual "
                   "{:.2e}), damage solver {} after {} iterations (KKT residual {:.2e}, beta in [{}, {}]); tolerance "
                   "{:.1e}. Results up to step {} are in '{}'\n",
                   r.n, r.t, r.contact.converged ? "converged" : "did not converge", r.contact.iterations,
                   r.contact.residuals.max(), r.damage.converged ? "converged" : "did not converge",
                   r.damage.iterations, r.damage.kkt_residual, r.beta_min, r.beta_max,
                   c.solvers.residual_tolerance, r.n - 1, output.directory().string());
      return 1;
    }
    output.record(r);
    progress.update(r);
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  output.finish(wall);
  if (!o.quiet && rank == 0)
    fmt::print("  done in {:.3f} s; results in {}/ (solution.pvd, history.csv, probes.csv, summary.json)\n", wall,
               output.directory().string());
  if (o.plot && rank == 0) {
    const std::string cmd = fmt::format("/usr/bin/python3 '{}/scripts/vpcontact_plot.py' '{}'", VPC_SOURCE_DIR,
                                        output.directory().string());
    require(std::system(cmd.c_str()) == 0, "plot: drawing the figures of '{}' failed", output.directory().string());
  }
  return 0;
}

}  // namespace

int parallel_run(Case& c, const ParallelRunOptions& o) {
  if (PetscInitializeNoArguments() != 0) {
    fmt::print(stderr, "vpcontact: error: PETSc/MPI could not be initialized\n");
    return 2;
  }
  // One thread per rank (pure MPI) unless OMP_NUM_THREADS says otherwise; the
  // BLAS inside MUMPS likewise.
  if (!std::getenv("OMP_NUM_THREADS")) omp_set_num_threads(1);
  set_blas_threads(1);
  const MPI_Comm comm = PETSC_COMM_WORLD;
  const int rank = comm_rank(comm), size = comm_size(comm);
  // Choices every rank rejects alike: said once, and no abort needed.
  try {
    require(o.resume.empty(), "--resume: the PETSc engine writes no checkpoints yet (docs/parallel.md); "
                              "resume with the serial engine (--engine serial) from a serial run's checkpoints");
    require(o.halvings == 0, "--retry-halvings: the PETSc engine does not retry failed steps yet");
    PetscLinearSolver check(comm, "vpc_check_", {o.linear_solver});
  } catch (const Error& e) {
    if (rank == 0) fmt::print(stderr, "vpcontact: error: {}\n", e.what());
    PetscFinalize();
    return 1;
  }
  int rc = 0;
  try {
    rc = run(c, o, comm);
  } catch (const std::exception& e) {
    // One rank's failure must not leave the others waiting in a collective call.
    std::fflush(stdout);
    fmt::print(stderr, "vpcontact: error{}: {}\n", size > 1 ? fmt::format(" (rank {} of {})", rank, size) : "",
               e.what());
    std::fflush(stderr);
    if (size > 1) MPI_Abort(comm, 1);
    rc = 1;
  }
  PetscFinalize();
  return rc;
}

}  // namespace vpc
