#include "parallel_run.hpp"

#include "child_process.hpp"
#include "interrupt.hpp"
#include "io/output_files.hpp"

#include "parallel/distributed_time_stepper.hpp"
#include "parallel/parallel_checkpoint.hpp"
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

/// An error every rank meets alike: reported once, by rank 0, without an abort.
struct CollectiveError : Error {
  using Error::Error;
};

void describe(const Case& c, const DistributedTimeStepper& stepper, int size, const std::string& linear) {
  const auto& p = stepper.problem();
  const auto& part = stepper.part();
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

/// `work` on rank 0 only; its error is then every rank's (CollectiveError).
template <typename F>
void on_rank_0(MPI_Comm comm, F&& work) {
  std::string error;
  if (comm_rank(comm) == 0) {
    try {
      work();
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  int error_size = static_cast<int>(error.size());
  MPI_Bcast(&error_size, 1, MPI_INT, 0, comm);
  if (error_size == 0) return;
  error.resize(static_cast<size_t>(error_size));
  MPI_Bcast(error.data(), error_size, MPI_CHAR, 0, comm);
  throw CollectiveError(error);
}

/// The signal any rank has received (SIGINT/SIGTERM), 0 if none: every rank
/// agrees, so that all stop after the same step.
int interrupt_everywhere(MPI_Comm comm) {
  int local = interrupt_signal(), any = 0;
  MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

/// The case on every rank, its mesh on rank 0 only: rank 0 builds it and sends
/// the mesh's dimension (or its error, which every rank then reports alike); the
/// other ranks build everything else (laws and formulas are C++ objects made by
/// the parser) around an empty mesh of that dimension.
Case load_everywhere(const CaseLoader& load, MPI_Comm comm) {
  const int rank = comm_rank(comm);
  Case c;
  int dim = 0;
  on_rank_0(comm, [&] {
    c = load({});
    dim = c.problem->mesh.dim();
  });
  MPI_Bcast(&dim, 1, MPI_INT, 0, comm);
  if (rank != 0) c = load({.build = false, .dim = dim});
  return c;
}

int run(const CaseLoader& load, const ParallelRunOptions& o, MPI_Comm comm) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const int rank = comm_rank(comm), size = comm_size(comm);
  // Before any set-up, as the serial run: the header, then the output directory's check.
  on_rank_0(comm, [&] {
    if (!o.quiet) fmt::print("{}\n", o.header);
    std::fflush(stdout);
    if (!o.resume.empty())
      require(std::filesystem::is_directory(o.output_directory),
              "--resume: no good checkpoint for this case in '{}': it is not a directory", o.resume);
    prepare_output_directory(o.output_directory);
    remove_temporary_files(o.output_directory);
  });
  Case c = load_everywhere(load, comm);
  c.solvers.max_halvings = o.halvings;
  try {  // what the engine refuses (DistributedTimeStepper's rule): said once, before any set-up
    require_petsc_engine_supports(c.solvers);
  } catch (const Error& e) {
    throw CollectiveError(e.what());
  }
  PetscSolverOptions linear;
  linear.kind = o.linear_solver;

  if (const int s = interrupt_everywhere(comm)) throw Interrupted(s);
  DistributedMesh part = distribute_mesh(comm, *c.problem);
  c.problem->mesh = Mesh();  // from here on, rank 0 too holds its part only
  StageLog log(o.quiet || rank != 0);
  c.solvers.on_setup_stage = std::ref(log);  // collective stages: a signal is looked at after them all
  DistributedTimeStepper stepper(c.problem, std::move(part), c.solvers, linear);
  if (const int s = interrupt_everywhere(comm)) throw Interrupted(s);
  if (!o.quiet && rank == 0) describe(c, stepper, size, linear.kind);
  ParallelOutput output(stepper, c.output, linear.kind);
  const std::string case_name = c.name;
  auto checkpoint = [&] {
    write_checkpoint(stepper, output.directory(), case_name, output.pvd_entries(), output.totals());
  };
  int last_checkpoint = 0;
  if (!o.resume.empty()) {
    std::vector<std::string> skipped;
    const auto saved = resume_from_checkpoint(stepper, o.resume, &skipped);
    if (rank == 0)
      for (const auto& s : skipped) fmt::print(stderr, "vpcontact: skipping {}\n", s);
    if (!saved)
      throw CollectiveError(fmt::format("--resume: no good checkpoint for this case in '{}'{}", o.resume,
                                        skipped.empty() ? "" : " (see the files skipped above)"));
    output.resume(saved->n, saved->pvd, saved->totals);
    last_checkpoint = saved->n;
    if (!o.quiet && rank == 0)
      fmt::print("  resuming from the checkpoint of step {} (t = {}) on {} rank{}\n", saved->n, saved->t, size,
                 size > 1 ? "s" : "");
  } else {
    on_rank_0(comm, [&] {  // stale solution_*.vtu, and checkpoints not to resume from (as the serial run)
      const auto removed = remove_run_outputs(output.directory());
      if (!o.quiet && !removed.empty())
        fmt::print("  removed {} file{} of an earlier run from {}/\n", removed.size(), removed.size() > 1 ? "s" : "",
                   output.directory().string());
    });
    output.start();
    checkpoint();
  }
  // Checkpoints as in the serial engine; by time on rank 0's clock.
  CheckpointSchedule schedule(o.checkpoint_every, o.checkpoint_seconds);
  auto checkpoint_due = [&](int n) {
    int due = schedule.due(n);
    if (schedule.by_time()) MPI_Bcast(&due, 1, MPI_INT, 0, comm);
    return due != 0;
  };
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
                   "{:.1e}. Results up to step {} are in '{}'; `--resume {}` continues from step {}\n",
                   r.n, r.t, r.contact.converged ? "converged" : "did not converge", r.contact.iterations,
                   r.contact.residuals.max(), r.damage.converged ? "converged" : "did not converge",
                   r.damage.iterations, r.damage.kkt_residual, r.beta_min, r.beta_max,
                   c.solvers.residual_tolerance, r.n - 1, output.directory().string(), output.directory().string(),
                   last_checkpoint);
      return 1;
    }
    output.record(r);
    progress.update(r);
    const int signal = interrupt_everywhere(comm);  // as the serial loop: stop after this step, on every rank
    if (stepper.done() || signal || checkpoint_due(r.n)) {
      checkpoint();
      last_checkpoint = r.n;
      schedule.written();
    }
    if (signal && !stepper.done()) {
      progress.finish();
      output.finish(std::chrono::duration<double>(Clock::now() - t0).count());
      if (rank == 0) {
        remove_temporary_files(output.directory());
        std::fflush(stdout);
        fmt::print(stderr,
                   "vpcontact: interrupted by {} after step {} of {} (t = {:.6g}); checkpoint written in {}/. To "
                   "continue:\n  {}\n",
                   signal_name(signal), r.n, c.problem->n_steps, r.t, output.directory().string(),
                   resume_command(o.argv, output.directory(), size));
      }
      return 128 + signal;
    }
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  output.finish(wall);
  if (rank == 0) remove_temporary_files(output.directory());
  if (!o.quiet && rank == 0)
    fmt::print("  done in {:.3f} s; results in {}/ (solution.pvd, history.csv, probes.csv, summary.json)\n", wall,
               output.directory().string());
  if (o.plot) on_rank_0(comm, [&] { draw_figures(output.directory(), o.plot_options, true); });
  return 0;
}

}  // namespace

int parallel_run(const CaseLoader& load, const ParallelRunOptions& o) {
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
    PetscLinearSolver check(comm, "vpc_check_", {o.linear_solver});
  } catch (const Error& e) {
    if (rank == 0) fmt::print(stderr, "vpcontact: error: {}\n", e.what());
    PetscFinalize();
    return 1;
  }
  int rc = 0;
  catch_interrupts();
  try {
    rc = run(load, o, comm);
  } catch (const Interrupted& e) {  // every rank alike (interrupt_everywhere)
    if (rank == 0) fmt::print(stderr, "\nvpcontact: {}\n", e.what());
    rc = 128 + e.signal;
  } catch (const CollectiveError& e) {
    if (rank == 0) fmt::print(stderr, "vpcontact: error: {}\n", e.what());
    rc = 1;
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
