#include "parallel/petsc_engine.hpp"

#include "parallel/collective.hpp"
#include "parallel/distributed_time_stepper.hpp"
#include "parallel/parallel_checkpoint.hpp"
#include "parallel/parallel_output.hpp"
#include "run/progress.hpp"

#include <fmt/format.h>

#include <optional>

namespace vpc {

namespace {

/// The signal any rank has received (SIGINT/SIGTERM), 0 if none: every rank
/// agrees, so that all stop after the same step.
int interrupt_anywhere(MPI_Comm comm) {
  int local = interrupt_signal(), any = 0;
  MPI_Allreduce(&local, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

class PetscEngine final : public Engine {
 public:
  PetscEngine(Case c, DistributedMesh part, std::string linear_solver)
      : case_(std::move(c)), stepper_(case_.problem, std::move(part), case_.solvers, {linear_solver}),
        linear_solver_(std::move(linear_solver)),
        comm_(stepper_.part().comm), rank_(comm_rank(comm_)), size_(comm_size(comm_)) {}

  bool done() const override { return stepper_.done(); }
  StepReport step() override { return stepper_.step(); }
  int n_steps() const override { return stepper_.problem().n_steps; }
  double tolerance() const override { return case_.solvers.residual_tolerance; }
  bool halves_failed_steps() const override { return false; }

  void open_output() override { output_.emplace(stepper_, case_.output, linear_solver_); }
  const std::filesystem::path& directory() const override { return output_->directory(); }
  void start() override { output_->start(); }
  void record(const StepReport& r) override { output_->record(r); }
  void finish(double wall_seconds) override { output_->finish(wall_seconds); }
  void checkpoint() override {
    write_checkpoint(stepper_, output_->directory(), case_.name, output_->pvd_entries(), output_->totals());
  }
  std::optional<ResumedAt> resume(const std::filesystem::path& dir, std::vector<std::string>& skipped) override {
    const auto saved = resume_from_checkpoint(stepper_, dir, &skipped);
    if (!saved) return std::nullopt;
    output_->resume(saved->n, saved->pvd, saved->totals);
    return ResumedAt{saved->n, saved->t};
  }

  bool root() const override { return rank_ == 0; }
  int ranks() const override { return size_; }
  int interrupt_anywhere() const override { return vpc::interrupt_anywhere(comm_); }
  bool root_decides(bool value) const override {
    int v = value;
    MPI_Bcast(&v, 1, MPI_INT, 0, comm_);
    return v != 0;
  }
  void on_root(const std::function<void()>& work) override { vpc::on_root(comm_, work); }

  /// What set-up found; rank 0 prints it.
  void describe() const {
    const auto& part = stepper_.part();
    fmt::print("  PETSc engine on {} MPI rank{}: linear solver {}{}\n", size_, size_ > 1 ? "s" : "", linear_solver_,
               stepper_.keeps_w() ? "" : " (K^-1 N^T not kept: two solves per step)");
    fmt::print("  mesh: d = {}, {} nodes, {} cells; {} free displacement dofs, {} contact nodes\n", part.mesh.dim(),
               part.n_global_nodes, part.n_global_cells, part.n_global_dofs, part.n_contact);
    describe_data(stepper_.problem(), case_.solvers, stepper_.setup_timing().total);
  }

 private:
  Case case_;
  DistributedTimeStepper stepper_;
  std::string linear_solver_;
  MPI_Comm comm_;
  int rank_, size_;
  std::optional<ParallelOutput> output_;
};

/// Throws Interrupted on every rank if any has received a signal.
void stop_if_interrupted_anywhere(MPI_Comm comm) {
  if (const int s = interrupt_anywhere(comm)) throw Interrupted(s);
}

/// The case on every rank, its mesh on rank 0 only: rank 0 builds it and sends
/// the mesh's dimension (or its error, which every rank then reports alike); the
/// other ranks build everything else (laws and formulas are C++ objects made by
/// the parser) around an empty mesh of that dimension.
Case load_everywhere(const CaseLoader& load, MPI_Comm comm) {
  Case c;
  int dim = 0;
  on_root(comm, [&] {
    c = load({});
    dim = c.problem->mesh.dim();
  });
  MPI_Bcast(&dim, 1, MPI_INT, 0, comm);
  if (comm_rank(comm) != 0) c = load({.build = false, .dim = dim});
  return c;
}

}  // namespace

std::unique_ptr<Engine> set_up_petsc(MPI_Comm comm, const CaseLoader& load, const RunOptions& o) {
  const int rank = comm_rank(comm);
  on_root(comm, [&] { begin_run(o); });
  Case c = load_everywhere(load, comm);
  c.solvers.max_halvings = o.halvings;
  // What the engine does not do yet (DistributedTimeStepper's rule): said once, before any set-up.
  collective(comm, [&] { require_petsc_engine_supports(c.solvers); });
  stop_if_interrupted_anywhere(comm);
  DistributedMesh part = distribute_mesh(comm, *c.problem);
  c.problem->mesh = Mesh();  // from here on, rank 0 too holds its part only
  // Collective stages: a signal is looked at after them all.
  c.solvers.on_setup_stage = StageLog(o.quiet || rank != 0);
  auto engine = std::make_unique<PetscEngine>(std::move(c), std::move(part), o.linear_solver);
  stop_if_interrupted_anywhere(comm);
  if (!o.quiet && rank == 0) engine->describe();
  return engine;
}

}  // namespace vpc
