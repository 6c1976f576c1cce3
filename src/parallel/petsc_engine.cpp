#include "parallel/petsc_engine.hpp"

#include "la/petsc.hpp"
#include "mesh/mesh_bytes.hpp"
#include "parallel/block_part.hpp"
#include "parallel/distributed_mesh.hpp"
#include "run/progress.hpp"
#include "run/solver_plan.hpp"
#include "solvers/contact_capabilities.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <optional>

namespace vpc {

namespace {

/// Throws Interrupted on every rank if any has received a signal.
void stop_if_interrupted_anywhere(const la::Comm& comm) {
  if (const int s = static_cast<int>(comm.max(interrupt_signal()))) throw Interrupted(s);
}

/// Rank 0's `coarse` (or none) on every rank, as mesh_bytes. Collective.
std::shared_ptr<const Mesh> broadcast_coarse_mesh(const la::Comm& comm, const std::shared_ptr<const Mesh>& coarse) {
  std::string bytes = comm.rank() == 0 && coarse ? mesh_bytes(*coarse) : std::string();
  comm.broadcast(bytes);
  if (bytes.empty()) return nullptr;
  return comm.rank() == 0 ? coarse : std::make_shared<const Mesh>(mesh_from_bytes(bytes));
}

}  // namespace

// Rank 0 builds the case and sends the mesh's dimension (or its error, which every
// rank then reports alike); the other ranks build everything else (laws and
// formulas are C++ objects made by the parser) around an empty mesh of that dimension.
// A generated mesh of one body is built by blocks instead, each rank its own (MeshRequest::block),
// and so is a refined file's mesh, which only rank 0 reads (MeshRequest::coarse); the caller then
// checks the case on all blocks together (validate_blocks).
Case load_case_everywhere(const CaseLoader& load, const la::Comm& comm) {
  Case c;
  double dim = 0;
  MeshRequest request;
  if (comm.size() > 1) request.block = MeshRequest::Block{comm.rank(), comm.size()};
  la::on_root(comm, [&] {
    c = load(request);
    dim = c.problem->mesh.dim();
  });
  dim = la::broadcast(comm, std::vector<double>{dim})[0];
  // A refined file's mesh: rank 0's to every rank, which refines its part of it without reading the file.
  if (comm.size() > 1) request.coarse = broadcast_coarse_mesh(comm, comm.rank() == 0 && c.problem->block ? c.problem->block->coarse : nullptr);
  la::collective(comm, [&] {
    if (comm.rank() == 0) return;
    request.build = false;  // the whole mesh, where it is not built by blocks, comes from rank 0 (distribute_mesh)
    request.dim = static_cast<int>(dim);
    c = load(request);
  });
  return c;
}

namespace {

/// `rows`: the problem's contact rows as its validation built them (Case::contact_rows); null: built
/// with its validation here.
std::unique_ptr<TimeStepper> distributed_stepper(MPI_Comm mpi_comm, std::shared_ptr<const Problem> problem,
                                                 const SolverChoice& choice, PetscSolverOptions linear,
                                                 ContactRows rows = nullptr) {
  // Spread rows (--spread-pairs) are the dual's alone: another solver asked is refused here, on every
  // rank, as the contact set-up would refuse it, but before the mesh is cut and K factorized.
  ContactNeeds spread;
  spread.spread_pairs = problem->contact.spreads_pairs(choice.spread_pairs);
  refuse_unsolvable(choice.contact, spread);
  MeshPart part = problem->block ? make_mesh_part(block_part_pieces(mpi_comm, *problem, std::move(rows)))
                                 : distribute_mesh(mpi_comm, *problem, {}, std::move(rows), choice.spread_pairs);
  // Iterative solves stop 100x under the relative residual a step accepts (solver.tolerance,
  // 1e-8): tighter only costs iterations (at 1e-12, a third more on foundation-3d).
  linear.rtol = 1e-2 * choice.residual_tolerance;
  return std::make_unique<TimeStepper>(std::move(problem), std::move(part),
                                       la::make_petsc_backend(la::make_mpi_comm(mpi_comm), linear), choice);
}

}  // namespace

std::unique_ptr<TimeStepper> petsc_stepper(MPI_Comm mpi_comm, Case& c, PetscSolverOptions linear) {
  auto stepper = distributed_stepper(mpi_comm, c.problem, c.solvers, std::move(linear), c.contact_rows);
  // From here on, rank 0 too holds its part only (a large-sliding pair's slider keeps its surfaces:
  // scheme/pair_slider.hpp).
  c.contact_rows.reset();
  c.problem->mesh = Mesh();
  if (MeshBlock* b = c.problem->block.get()) {  // a block's numbers, not needed once the part is cut
    std::vector<int>().swap(b->node_id);
    std::vector<int>().swap(b->cell_id);
    std::vector<int>().swap(b->cell_rank);
  }
  return stepper;
}

EngineChoice petsc_engine(MPI_Comm comm, const std::string& linear_solver) {
  return {[comm, linear_solver](const CaseLoader& load, const RunOptions& o) {
            RunOptions with = o;
            with.linear_solver = linear_solver;
            return set_up_petsc(comm, load, with);
          },
          [comm, linear_solver](std::shared_ptr<const Problem> problem, const SolverChoice& choice) {
            PetscSolverOptions linear;
            linear.kind = linear_solver.empty() ? "mumps" : linear_solver;
            return distributed_stepper(comm, std::move(problem), choice, linear);
          },
          la::make_mpi_comm(comm).rank() == 0, la::make_mpi_comm(comm)};
}

namespace {

/// The ranks of `comm` on this rank's machine, which share its memory. Collective.
int ranks_on_machine(MPI_Comm comm) {
  MPI_Comm machine;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &machine);
  int n = 1;
  MPI_Comm_size(machine, &n);
  MPI_Comm_free(&machine);
  return n;
}

/// The engine of the loaded case `c` on the ranks of `comm` with `plan`'s linear solver; with [adapt], the
/// adapted meshes' steppers made by `replanned` (empty: with the same linear solver). Collective.
std::unique_ptr<Run> engine_on_ranks(MPI_Comm mpi_comm, Case c, const RunOptions& o, const SolverPlan& plan,
                                     AdaptiveEngine replanned = {}) {
  const la::Comm comm = la::make_mpi_comm(mpi_comm);
  c.solvers.max_halvings = o.halvings;
  // Collective stages: a signal is looked at after them all.
  c.solvers.on_setup_stage = StageLog(o.quiet || comm.rank() != 0);
  PetscSolverOptions linear;
  linear.kind = plan.linear_solver;
  linear.products_row_by_row = plan.products_row_by_row;
  // [adapt] (on one rank: StepperRun refuses more): the coarse problem, which petsc_stepper empties of its
  // mesh, and new steppers of adapted meshes made as this one.
  AdaptiveEngine adaptive = std::move(replanned);
  if (c.adapt && !adaptive.make) {
    adaptive.coarse = std::make_shared<const Problem>(*c.problem);
    adaptive.make = [mpi_comm, linear](std::shared_ptr<const Problem> p, const SolverChoice& choice) {
      return distributed_stepper(mpi_comm, std::move(p), choice, linear);
    };
    adaptive.plan = fmt::format("each adapted mesh on the PETSc engine's {}, as the first", linear.kind);
  }
  auto stepper = petsc_stepper(mpi_comm, c, linear);
  stop_if_interrupted_anywhere(comm);
  return make_run(std::move(c), std::move(stepper), o.quiet, std::move(adaptive));
}

const std::vector<std::string> kLinearSolvers = {"mumps", "cg-gamg", "cg-hypre"};

/// A rank's part while rank 0 runs the case alone (SolverRequest::auto_route): no steps, no output; the
/// rank then waits for rank 0 (parallel_run's end, without spinning on a core).
class WaitingRun final : public Run {
 public:
  bool done() const override { return true; }
  StepReport step() override { return {}; }
  int n_steps() const override { return 0; }
  double final_time() const override { return 0; }
  double tolerance() const override { return 0; }
  void open_output() override {}
  const std::filesystem::path& directory() const override { return directory_; }
  void start() override {}
  void record(const StepReport&) override {}
  void finish(double) override {}
  void checkpoint() override {}
  std::optional<ResumedAt> resume(const std::filesystem::path&, std::vector<std::string>&) override {
    return ResumedAt{};
  }
  bool root() const override { return false; }

 private:
  std::filesystem::path directory_;
};

}  // namespace

std::unique_ptr<Run> set_up_petsc(MPI_Comm mpi_comm, const CaseLoader& load, const RunOptions& o) {
  const la::Comm comm = la::make_mpi_comm(mpi_comm);
  la::on_root(comm, [&] { begin_run(o); });
  Case c = load_case_everywhere(load, comm);
  // A mesh built by blocks: the case checked on all of them, its sizes summed over them.
  std::optional<ProblemSize> size;
  if (c.problem->block) {
    const StageLog log(o.quiet || comm.rank() != 0);
    const auto t0 = std::chrono::steady_clock::now();
    log("checking the case on every rank's block and summing their sizes", -1);
    c.contact_rows = validate_blocks(comm, *c.problem);
    size = block_problem_size(comm, *c.problem, c.contact_rows);
    log("", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    // What each rank built: its block, a part of the grid with a layer of cells around it.
    const double most = comm.max(static_cast<double>(c.problem->mesh.n_cells()));
    const MeshBlock& b = *c.problem->block;
    if (comm.rank() == 0 && !o.quiet)
      fmt::print("  mesh built by blocks on {} ranks: at most {:.0f} cells a rank, of {} ({:.1f} %){}\n", comm.size(), most,
                 b.whole_cells, 100.0 * most / static_cast<double>(b.whole_cells),
                 b.coarse ? fmt::format("; the file's {} cells refined {} time{}, read by rank 0 and sent to every rank",
                                        b.coarse->n_cells(), b.levels, b.levels == 1 ? "" : "s")
                          : std::string());
  }
  stop_if_interrupted_anywhere(comm);
  // Rank 0 (which holds the whole mesh, or the sizes summed over the blocks) chooses the linear
  // solver (or refuses) for every rank.
  const SolverRequest request{.engine = "petsc", .linear_solver = o.linear_solver, .ranks = comm.size(),
                              .ranks_on_machine = ranks_on_machine(mpi_comm), .auto_route = o.auto_route};
  // The linear solver's index in kLinearSolvers, products_row_by_row, and rank 0 alone (on CHOLMOD).
  std::vector<double> chosen(3, 0.0);
  la::on_root(comm, [&] {
    const SolverPlan plan = plan_run(c, request, o.quiet, size ? &*size : nullptr);
    chosen = {static_cast<double>(std::ranges::find(kLinearSolvers, plan.linear_solver) - kLinearSolvers.begin()),
              plan.products_row_by_row ? 1.0 : 0.0, plan.petsc ? 0.0 : 1.0};
  });
  chosen = la::broadcast(comm, chosen);
  if (chosen[2] != 0) {  // a small case (SolverRequest::auto_route); a mesh built by blocks built whole
    if (comm.rank() != 0) return std::make_unique<WaitingRun>();
    return set_up_on_one_process(c.problem->block ? load({}) : std::move(c), o);
  }
  SolverPlan plan;
  plan.linear_solver = kLinearSolvers.at(static_cast<std::size_t>(chosen[0]));
  plan.products_row_by_row = chosen[1] != 0;
  return engine_on_ranks(mpi_comm, std::move(c), o, plan);
}

namespace {

/// [adapt] under --engine auto on one process: each adapted mesh's engine and linear solver planned for it
/// as the first mesh's were (plan_solver), so that a run refined past what CHOLMOD does well (or fits) goes on
/// with CG + GAMG on the PETSc engine at one rank, and back where coarsening makes CHOLMOD the better choice
/// again (the state carries over either way: mesh_adaptivity.hpp). A change is printed, unless quiet.
/// `first`: the plan of the case's own mesh.
AdaptiveEngine replanning_adaptivity(const Case& c, const SolverPlan& first,
                                     const std::function<MPI_Comm()>& start_petsc, bool quiet) {
  AdaptiveEngine a;
  if (!c.adapt) return a;
  a.coarse = std::make_shared<const Problem>(*c.problem);  // (the PETSc engine's stepper empties its problem's mesh)
  a.plan = "each adapted mesh's engine and linear solver planned for it, as the first's (--engine auto)";
  auto last = std::make_shared<std::string>(first.linear_solver);
  a.make = [start_petsc, quiet, last](std::shared_ptr<const Problem> p,
                                      const SolverChoice& choice) -> std::unique_ptr<TimeStepper> {
    const SolverPlan plan = plan_solver(*p, choice, {.engine = "auto", .petsc_built = true});
    if (plan.linear_solver != *last) {
      if (!quiet)
        fmt::print("  [adapt] the adapted mesh ({} cells, {} nodes): {}\n", p->mesh.n_cells(), p->mesh.n_nodes(), plan.why);
      std::fflush(stdout);
      *last = plan.linear_solver;
    }
    if (!plan.petsc) return std::make_unique<TimeStepper>(std::move(p), choice);
    PetscSolverOptions linear;
    linear.kind = plan.linear_solver;
    linear.products_row_by_row = plan.products_row_by_row;
    return distributed_stepper(start_petsc(), std::move(p), choice, linear);
  };
  return a;
}

}  // namespace

EngineChoice auto_engine(const std::function<MPI_Comm()>& start_petsc) {
  EngineChoice e = serial_engine();
  e.set_up = [start_petsc](const CaseLoader& load, const RunOptions& o) -> std::unique_ptr<Run> {
    begin_run(o);
    Case c;
    SolverPlan plan;
    AdaptiveEngine adaptive;
    {
      const SetUpStopsAtOnce at_once;  // as set_up_serial, until the engine is known
      c = load({});
      plan = plan_run(c, {.engine = "auto", .petsc_built = true}, o.quiet);
      adaptive = replanning_adaptivity(c, plan, start_petsc, o.quiet);
      if (!plan.petsc) return set_up_on_one_process(std::move(c), o, std::move(adaptive));
    }
    return engine_on_ranks(start_petsc(), std::move(c), o, plan, std::move(adaptive));
  };
  return e;
}

}  // namespace vpc
