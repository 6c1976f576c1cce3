// The one engine of the run loop: a TimeStepper (on one process or on this
// process's part of a distributed mesh), RunOutput and the checkpoints of
// io/checkpoint.hpp. Whatever concerns the processes goes through la::Comm, so
// on one process every collective is the identity.
#include "adapt/mesh_adaptivity.hpp"
#include "core/quote.hpp"
#include "io/atomic_file.hpp"
#include "io/case_file.hpp"
#include "io/checkpoint.hpp"
#include "io/checkpoint_file.hpp"
#include "io/run_output.hpp"
#include "la/memory_estimate.hpp"
#include "run/output_space.hpp"
#include "run/progress.hpp"
#include "run/run_case.hpp"
#include "run/solver_plan.hpp"
#include "scheme/step_checks.hpp"
#include "scheme/step_failure.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

namespace vpc {

namespace {

/// Where an adaptive run's checkpoint of step n keeps its refinement history (JSON text; named like a
/// checkpoint's piece so that the checkpoints' clean-up and a fresh run's removal take it with them).
std::filesystem::path adaptation_history_file(const std::filesystem::path& dir, long long n) {
  return dir / fmt::format("checkpoint_{:05d}.adaptations.bin", n);
}

/// Where an adaptive run's checkpoint of step n keeps what undoes the adaptation made after step n, while the
/// step after it has not succeeded (a resume there can then undo it as the uninterrupted run would): the
/// refinement history before it, and the state it carried, on the mesh before (a whole-state file).
std::filesystem::path undo_history_file(const std::filesystem::path& dir, long long n) {
  return dir / fmt::format("checkpoint_{:05d}.undo.adaptations.bin", n);
}
std::filesystem::path undo_state_file(const std::filesystem::path& dir, long long n) {
  return dir / fmt::format("checkpoint_{:05d}.undo.bin", n);
}

class StepperRun final : public Run {
 public:
  StepperRun(Case c, std::unique_ptr<TimeStepper> stepper, AdaptiveEngine adaptive)
      : case_(std::move(c)), stepper_(std::move(stepper)), keys_(keys_of(case_)) {
    if (case_.adapt) {
      if (comm().size() > 1)
        throw CollectiveError(fmt::format(
            "{}: mesh adaptivity runs on one process for now (the serial engine, or the PETSc engine on one rank); "
            "under mpirun with {} ranks it is refused until adaptivity over ranks is built (docs/cases.md, [adapt])",
            case_.adapt->where, comm().size()));
      SolverChoice choice = stepper_->solvers();
      // A new mesh's set-up is part of a step: no stage lines, but a signal still stops it.
      choice.on_setup_stage = [](const std::string&, double seconds) {
        if (seconds >= 0) stop_if_interrupted();
      };
      adaptive_coarse_ = adaptive.coarse ? adaptive.coarse : case_.problem;
      adapt_choice_ = std::move(choice);
      adaptive_make_ = std::move(adaptive.make);
      adapt_plan_ = adaptive.plan.empty() ? "each adapted mesh on CHOLMOD, as the first (the serial engine)"
                                          : std::move(adaptive.plan);
      adapt_.emplace(adaptive_coarse_, adapt_choice_, *case_.adapt, adaptive_make_);
    }
  }

  bool done() const override { return stepper_->done(); }
  StepReport step() override {
    StepReport r = adapt_ ? adaptive_step() : stepper_->step();
    // Once a run: Tresca's bound acted through nodes not in contact (the same count on every rank).
    if (!warned_open_)
      if (const std::string w = open_friction_warning(stepper_->problem(), r); !w.empty()) {
        warned_open_ = true;
        if (root()) fmt::print(stderr, "vpcontact: warning: {}\n", w);
      }
    // Once a run: a surface law's state passed its warning threshold (SPEC §9's worn depth).
    if (!warned_surface_ && r.surface.warn_share > 1) {
      warned_surface_ = true;
      if (root()) fmt::print(stderr, "vpcontact: warning: at step {} (t = {:.6g}), {}\n", r.n, r.t, r.surface.warn_text);
    }
    return r;
  }
  int n_steps() const override { return stepper_->problem().n_steps; }
  double final_time() const override { return stepper_->problem().final_time; }
  double tolerance() const override { return case_.solvers.residual_tolerance; }

  void open_output() override {
    output_.emplace(*stepper_, case_.output);
    if (adapt_)
      output_->set_adaptation({[this] {
                                 const std::vector<int> level = adapt_->levels(*stepper_);
                                 return std::vector<VtuField>{
                                     {"level", 1, std::vector<double>(level.begin(), level.end()), true},
                                     {"indicator", 1, adapt_->indicator(*stepper_), false}};
                               },
                               &adapt_->log()});
  }
  const std::filesystem::path& directory() const override { return output_->directory(); }
  void start() override { output_->start(); }
  void record(const StepReport& r) override { output_->record(r); }
  void finish(double wall_seconds) override { output_->finish(wall_seconds); }
  void checkpoint() override {
    write_checkpoint(*stepper_, output_->directory(), case_.name, output_->pvd_entries(), output_->totals(), 0, 2,
                     keys_);
    // An adaptive run's refinement history beside it (after it: write_checkpoint clears what is not its
    // own at its step; a checkpoint without its history is skipped on resume, an older one taken).
    if (adapt_)
      on_root([&] {
        const std::filesystem::path& dir = output_->directory();
        const long long n = stepper_->state().n;
        if (undo_) write_undo(dir, n, *undo_);
        write_file_atomic(adaptation_history_file(dir, n), adapt_->history());
      });
    note_checkpoint();
  }
  std::optional<ResumedAt> resume(const std::filesystem::path& dir, std::vector<std::string>& skipped) override {
    auto saved = adapt_ ? resume_adapted(dir, skipped) : resume_from_checkpoint(*stepper_, dir, &skipped, keys_);
    if (!saved) return std::nullopt;
    note_checkpoint();
    output_->resume(saved->n, std::move(saved->pvd), saved->totals);
    ResumedAt at{saved->n, saved->t, {}};
    for (const ResumeChange& c : saved->changed) at.changed.push_back(describe_change(c));
    return at;
  }

  std::string check_output_space(int from) override {
    const OutputEstimate e = estimate_output(*stepper_, case_.output, from);  // the same on every process
    std::string line;
    on_root([&] {
      const std::filesystem::path dir =
          case_.output.directory.empty() ? std::filesystem::path("output") / case_.name : case_.output.directory;
      const double free = free_space(dir);
      const std::string warning = require_output_space(e, free, dir);
      if (!warning.empty()) fmt::print(stderr, "vpcontact: warning: {}\n", warning);
      line = fmt::format("output: {}; {} free where '{}' is", e.describe(), format_bytes(free), dir.string());
    });
    return line;
  }

  bool root() const override { return comm().rank() == 0; }
  int ranks() const override { return petsc() ? comm().size() : 0; }
  int interrupt_anywhere() const override { return static_cast<int>(comm().max(interrupt_signal())); }
  bool root_decides(bool value) const override { return comm().sum(root() && value ? 1.0 : 0.0) > 0; }
  void on_root(const std::function<void()>& work) override { la::on_root(comm(), work); }
  const TimeStepper* stepper() const override { return stepper_.get(); }
  void on_retire(std::function<void(TimeStepper&)> hook) override { retire_ = std::move(hook); }

  /// What set-up found, in global numbers; rank 0 prints it. Collective.
  void describe() const {
    const MeshPart& part = stepper_->part();
    double h_min = INFINITY, h_max = 0;
    if (part.mesh().n_cells() > 0) std::tie(h_min, h_max) = part.mesh().size_range();
    h_min = comm().min(h_min);
    h_max = comm().max(h_max);
    if (!root()) return;
    if (petsc())
      fmt::print("  PETSc engine on {} MPI rank{}: linear solver {}; {}{}\n", comm().size(), comm().size() > 1 ? "s" : "",
                 stepper_->backend().linear_solver(), stepper_->contact_method(),
                 part.pairs_spread               ? "; contact pairs' rows spread over the ranks (--spread-pairs)"
                 : case_.solvers.spread_pairs ? "; --spread-pairs: no contact pair to spread"
                                              : "");
    fmt::print("  mesh: d = {}, {} nodes, {} cells, h in [{:.3g}, {:.3g}]; {} free displacement dofs, {} contact "
               "nodes\n",
               part.dofs.dim(), part.n_global_nodes, part.n_global_cells, h_min, h_max, part.n_global_dofs,
               part.n_contact);
    SolverChoice solvers = case_.solvers;
    solvers.contact = stepper_->contact_solver();  // "auto" resolved
    describe_data(stepper_->problem(), solvers, stepper_->setup_seconds());
    if (adapt_) {
      // What the adaptivity may make: newest-vertex bisection halves the longest edge every d-th level.
      const AdaptSpec& a = adapt_->spec();
      fmt::print("  [adapt]: every {} step{}{}, Dörfler θ = {}, coarsening within {} of z, σ, β; cells down to h ≈ "
                 "{:.3g} (max_level {}), at most {} unknowns (d × nodes); {}; each new mesh's memory is checked as "
                 "a run's set-up is\n",
                 a.every, a.every > 1 ? "s" : "", a.resolve > 0 ? fmt::format(" (each redone up to {} times)", a.resolve) : "",
                 a.refine_fraction, a.coarsen_tolerance,
                 std::max(h_min / std::pow(2.0, a.max_level / part.dofs.dim()), a.min_size),
                 a.max_level, a.max_unknowns, adapt_plan_);
    }
  }

 private:
  /// A step of an adaptive run: the step, then where an adaptation is due, the mesh adapted from its
  /// solution (AdaptSpec::resolve times: the step redone on it from the state before it carried over;
  /// else once, carrying the step's state to the next step).
  StepReport adaptive_step() {
    const int n = stepper_->state().n + 1;
    bool due = !adapt_stopped_ && adapt_->due(n);
    const bool redo = due && adapt_->spec().resolve > 0;
    std::optional<Snapshot> before;
    std::vector<double> times_before;
    StepControlState control_before;
    if (redo) {
      before = stepper_->snapshot();
      times_before = stepper_->times();
      control_before = stepper_->step_control_state();
    }
    if (adapt_->spec().resolve == 0 && !adapt_stopped_ && stepper_->state().n == 0 && !undo_) {
      // Before the first step of a run that adapts between steps: the mesh adapted to what the forecast sees
      // (an obstacle about to touch Γ3: adapt/indicator.hpp, refined to max_level by one adaptation), so that
      // the first step's contact is resolved (nothing changes where nothing is about to touch); again while it
      // marks (what the forecast's zone added to the solution-driven marks), up to max_level times.
      for (int pass = 0; pass < adapt_->spec().max_level && !adapt_stopped_; ++pass) {
        Undo now = where_it_stands();
        std::unique_ptr<TimeStepper> next = adapt_or_recover(0, now.state, now.times, now.control, now);
        if (!next) break;
        swap_stepper(std::move(next));
        if (!undo_) undo_ = std::move(now);  // (the coarse mesh, before the first of these passes)
      }
    }
    StepReport r = stepper_->step();
    if (!r.ok && undo_) {
      // The step right after an adaptation failed, at its smallest step, on the adapted mesh: the adaptation
      // is undone (the mesh before it made again, the state it carried restored) and the step retried there.
      r = undo_adaptation(*undo_, r);
      due = false;  // (the same adaptation again would fail again: the next due step adapts)
    }
    undo_.reset();
    if (r.ok && due) {
      if (redo) {
        for (int pass = 1; pass <= adapt_->spec().resolve && r.ok; ++pass) {
          // (the pass's solution on its mesh: where the next mesh cannot be set up, or the step fails on it, the
          // run goes on from it)
          Undo last = where_it_stands(r);
          std::unique_ptr<TimeStepper> next = adapt_or_recover(pass, *before, times_before, control_before, last);
          if (!next) break;
          swap_stepper(std::move(next));
          before = stepper_->snapshot();  // the state before the step, on this mesh
          r = stepper_->step();
          if (!r.ok) {
            r = undo_adaptation(last, r);
            break;
          }
        }
      } else {
        // (the state the adaptation carries, kept in case the new mesh cannot be set up, or the next step fails
        // on it)
        Undo last = where_it_stands();
        if (std::unique_ptr<TimeStepper> next = adapt_or_recover(0, last.state, last.times, last.control, last)) {
          swap_stepper(std::move(next));
          undo_ = std::move(last);
        }
      }
      for (const std::string& w : adapt_->take_warnings())
        if (root()) fmt::print(stderr, "vpcontact: warning: {}\n", w);
    }
    r.mesh_cells = stepper_->part().n_global_cells;
    r.mesh_unknowns = stepper_->part().n_global_dofs;
    r.adaptations = static_cast<int>(adapt_->log().size());
    return r;
  }

  /// What an adaptation is undone to: the refinement history before it, the state on that mesh (with the
  /// step's times and controller), and for a redo pass the report of the step solved on it.
  struct Undo {
    std::string history;
    Snapshot state;
    std::vector<double> times;
    StepControlState control;
    std::optional<StepReport> report;
  };

  /// The run as it stands: its refinement history, state, times and controller (and `report`, the step just
  /// solved on this mesh, for a redo pass).
  Undo where_it_stands(std::optional<StepReport> report = {}) const {
    return {adapt_->history(), stepper_->snapshot(), stepper_->times(), stepper_->step_control_state(), std::move(report)};
  }

  /// Makes the mesh of `u.history` again (the stepper of the mesh it replaces freed first) and restores
  /// `u.state`, its times and controller on it; the output follows.
  void remake(const Undo& u) {
    if (stepper_) release_stepper()();
    stepper_ = adaptivity_from(u.history);
    stepper_->restore({u.state.state, u.state.u_free, stepper_->contact_warm_state(), stepper_->damage_warm_state()});
    stepper_->set_step_history(u.times, u.control);
    if (output_) output_->remesh(*stepper_);
  }

  /// The mesh of `u.history` made again (remake), warned; then u.report where the step was already solved
  /// there (a redo pass), else the step retried. `failed`: the step that failed on the adapted mesh (what
  /// the warning names).
  StepReport undo_adaptation(const Undo& u, const StepReport& failed) {
    const int adapted_at = u.state.state.n;
    const long long adapted_cells = stepper_->part().n_global_cells;
    remake(u);
    if (root())
      fmt::print(stderr, "vpcontact: warning: {}: step {} (t = {:.6g}) failed on the mesh adapted at step {} ({} cells: {}); "
                         "the adaptation is undone and the run goes on with the mesh before it ({} cells){}\n",
                 case_.adapt->where, failed.n, failed.t, adapted_at, adapted_cells,
                 step_failure(failed, case_.solvers.residual_tolerance), stepper_->part().n_global_cells,
                 u.report ? "" : ", where the step is taken again");
    return u.report ? *u.report : stepper_->step();
  }

  /// MeshAdaptivity::adapt carrying `carry`'s state (with `times`, `control`); where the adapted mesh cannot be
  /// set up (its memory refused, a degenerate cell), `back` is made again (remake: for a redo pass, the pass's
  /// solution on the mesh before, not the state before the step, which would be solved again), the
  /// adaptivity stopped for the rest of the run and the reason warned: the run goes on, on the mesh it had.
  /// Returns the new stepper, or null (nothing to change, or recovered: stepper_ is set).
  std::unique_ptr<TimeStepper> adapt_or_recover(int pass, const Snapshot& carry, std::vector<double> times,
                                                const StepControlState& control, const Undo& back) {
    try {
      return adapt_->adapt(*stepper_, pass, carry.state, std::move(times), control, release_stepper());
    } catch (const Error& e) {
      if (stepper_) throw;  // failed before the old mesh was released: nothing to recover
      remake(back);
      adapt_stopped_ = true;
      if (root())
        fmt::print(stderr, "vpcontact: warning: {}: the mesh adapted at step {} (t = {:.6g}) could not be set up ({}); "
                           "the run goes on with the mesh before it and adapts no further\n",
                   case_.adapt->where, back.state.state.n, back.state.state.t, e.what());
      return nullptr;
    }
  }

  /// Frees the stepper of the mesh being replaced once its state is carried, before the new one is made:
  /// their factors are never held together (the heap given back to the system: glibc keeps freed pages).
  /// If making the new one fails, adapt_or_recover makes the mesh before it again.
  std::function<void()> release_stepper() {
    return [this] {
      if (retire_) retire_(*stepper_);
      stepper_.reset();
      malloc_trim(0);
    };
  }

  /// The adaptivity made again from the coarse mesh by `history` (MeshAdaptivity::history; empty: none),
  /// and the stepper of the mesh it leaves.
  std::unique_ptr<TimeStepper> adaptivity_from(const std::string& history) {
    adapt_.emplace(adaptive_coarse_, adapt_choice_, *case_.adapt, adaptive_make_);
    if (!history.empty()) adapt_->replay(history);
    return adapt_->make_stepper();
  }

  /// An adaptive run's resume: for each checkpoint, newest first, its mesh made again from the coarse one by
  /// its refinement history (none: the coarse mesh), then the checkpoint of that step restored on it.
  std::optional<ResumePoint> resume_adapted(const std::filesystem::path& dir, std::vector<std::string>& skipped) {
    for (const long long n : checkpoint_file::checkpoint_steps(dir)) {
      const std::filesystem::path file = adaptation_history_file(dir, n);
      std::error_code ec;
      std::string history;
      if (std::filesystem::exists(file, ec)) {
        history = read_text_file(file, "adaptation history");
      } else if (n > 0) {
        skipped.push_back(fmt::format("{}: no refinement history beside it ({})", checkpoint_file::main_file(dir, n).string(),
                                      file.filename().string()));
        continue;
      }
      std::optional<Undo> undo;
      try {
        undo = read_undo(dir, n);
      } catch (const Error& e) {
        skipped.push_back(fmt::format("{}: {}", checkpoint_file::main_file(dir, n).string(), e.what()));
        continue;
      }
      swap_stepper(adaptivity_from(history));
      std::optional<ResumePoint> saved = resume_from_checkpoint(*stepper_, dir, &skipped, keys_);
      if (saved && saved->n == n) {
        undo_ = std::move(undo);
        return saved;
      }
    }
    return std::nullopt;
  }

  /// Writes `u` beside the checkpoint of step n (undo_history_file, undo_state_file; each atomically, the
  /// state first: a resume looks for the state only where the history is there).
  void write_undo(const std::filesystem::path& dir, long long n, const Undo& u) const {
    Checkpoint c;
    c.case_name = case_.name;
    c.problem_key = fmt::format("the state before the adaptation after step {}", n);
    c.snapshot = u.state;
    c.times = u.times;
    c.step_control = u.control.values();
    write_state_file(undo_state_file(dir, n), c);
    write_file_atomic(undo_history_file(dir, n), u.history);
  }

  /// What undoes the adaptation made after step n, kept beside its checkpoint (write_undo); none where no
  /// adaptation was pending at that step. Throws vpc::Error where its state is missing or damaged.
  static std::optional<Undo> read_undo(const std::filesystem::path& dir, long long n) {
    std::error_code ec;
    if (!std::filesystem::exists(undo_history_file(dir, n), ec)) return std::nullopt;
    const std::filesystem::path state = undo_state_file(dir, n);
    if (!std::filesystem::exists(state, ec))
      fail("the undo of its adaptation has a refinement history but no state ({} is missing)", state.filename().string());
    Checkpoint c = read_checkpoint(state);
    require(c.snapshot.state.n == n, "{}: the state of step {}, not {}", state.string(), c.snapshot.state.n, n);
    return Undo{read_text_file(undo_history_file(dir, n), "adaptation history"), std::move(c.snapshot), std::move(c.times),
                StepControlState::from_values(c.step_control), std::nullopt};
  }

  /// The run goes on with `next` (the adapted mesh); its output follows.
  void swap_stepper(std::unique_ptr<TimeStepper> next) {
    if (stepper_ && retire_) retire_(*stepper_);
    stepper_ = std::move(next);
    if (output_) output_->remesh(*stepper_);
  }

  bool warned_open_ = false, warned_surface_ = false;
  const la::Comm& comm() const { return stepper_->comm(); }
  bool petsc() const { return stepper_->backend().engine() == "petsc"; }

  /// The case's keys as its checkpoints record them: the keys read, with the solver settings
  /// in use (the command line's --contact-solver, --damage-solver, --tolerance, and the
  /// defaults) and whether VTU files are written (--no-vtu).
  static CaseKeys keys_of(const Case& c) {
    CaseKeys keys = c.keys;
    auto set = [&](const std::string& key, std::string value) {
      const auto at = std::find_if(keys.begin(), keys.end(), [&](const auto& k) { return k.first == key; });
      if (at != keys.end())
        at->second = std::move(value);
      else
        keys.emplace_back(key, std::move(value));
    };
    set("solver.contact", case_key_string(c.solvers.contact));
    set("solver.damage", case_key_string(c.solvers.damage));
    set("solver.tolerance", fmt::format("{}", c.solvers.residual_tolerance));
    set("output.vtu", c.output.vtu ? "true" : "false");
    return keys;
  }

  Case case_;
  std::unique_ptr<TimeStepper> stepper_;
  CaseKeys keys_;
  std::optional<RunOutput> output_;
  std::optional<MeshAdaptivity> adapt_;  // [adapt]: the mesh changes during the run
  std::function<void(TimeStepper&)> retire_;  // on_retire's hook
  bool adapt_stopped_ = false;  // an adapted mesh could not be set up: no further adaptation
  std::optional<Undo> undo_;     // the last adaptation (carried to the next step), until that step succeeds
  std::shared_ptr<const Problem> adaptive_coarse_;  // what makes it again (a resume)
  SolverChoice adapt_choice_;
  StepperMaker adaptive_make_;
  std::string adapt_plan_;  // how each adapted mesh's engine and linear solver are chosen (AdaptiveEngine::plan)
};

}  // namespace

void describe_data(const Problem& p, const SolverChoice& solvers, double setup_seconds) {
  std::string held = p.clamped.empty() ? "" : fmt::format("Γ1 (clamped): {}; ", fmt::join(p.clamped, ", "));
  if (!p.symmetry.empty()) held += fmt::format("symmetry: {}; ", fmt::join(p.symmetry, ", "));
  for (const PrescribedDisplacement& d : p.displacement) {
    std::string comps;
    for (int i = 0; i < 3; ++i)
      if (d.value[i]) comps += fmt::format("{}u{}", comps.empty() ? "" : ", ", "xyz"[i]);
    held += fmt::format("{} prescribed on {}; ", comps, fmt::join(d.parts, ", "));
  }
  fmt::print("  {}{}\n", held, fmt::join(p.contact.describe(), "; "));
  fmt::print("  elasticity: {} (E = {}, nu = {}); G: {}; phi: {}\n", p.elasticity.name(), p.elasticity.young(),
             p.elasticity.poisson(), p.law->describe(), printable(p.source->describe(), 200));
  for (const Material& m : p.materials)
    fmt::print("  material {} on {}: E = {}, nu = {}; G: {}; phi: {}\n", quote(m.name),
               printable(fmt::format("{}", fmt::join(m.regions, ", "))), m.elasticity.young(), m.elasticity.poisson(),
               m.law->describe(), printable(m.source->describe(), 200));
  fmt::print("  kappa = {}; T = {}, {}; solvers: contact {}, damage {}; setup {:.3f} s\n", p.kappa, p.final_time,
             p.describe_steps(), solvers.contact, solvers.damage, setup_seconds);
  std::fflush(stdout);
}

std::unique_ptr<Run> make_run(Case c, std::unique_ptr<TimeStepper> stepper, bool quiet, AdaptiveEngine adaptive) {
  auto engine = std::make_unique<StepperRun>(std::move(c), std::move(stepper), std::move(adaptive));
  if (!quiet) engine->describe();
  return engine;
}

SolverPlan plan_run(const Case& c, const SolverRequest& request, bool quiet, const ProblemSize* size) {
  const StageLog log(quiet);
  const auto t0 = std::chrono::steady_clock::now();
  log("choosing the linear solver (symbolic analysis of the node graph)", -1);
  SolverPlan plan;
  try {
    plan = plan_solver(*c.problem, size ? *size : problem_size(*c.problem, c.contact_rows), c.solvers, request,
                       memory_limit(c.solvers.memory_limit));
  } catch (const MemoryLimitError&) {
    if (!quiet) fmt::print(" refused\n");  // the stage's line closed before the error
    std::fflush(stdout);
    throw;
  }
  log("", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  if (!quiet) fmt::print("  {}\n", plan.why);
  std::fflush(stdout);
  return plan;
}

std::unique_ptr<Run> set_up_on_one_process(Case c, const RunOptions& o, AdaptiveEngine adaptive) {
  StageLog log(o.quiet);
  c.solvers.max_halvings = o.halvings;
  c.solvers.on_setup_stage = [log](const std::string& stage, double seconds) {  // a copy: it outlives set-up
    log(stage, seconds);
    if (seconds >= 0) stop_if_interrupted();
  };
  // --spread-pairs acts on the PETSc engine's ranks: said, not silently passed over.
  if (c.solvers.spread_pairs && !o.quiet)
    fmt::print("  --spread-pairs: one process, nothing to spread (every contact pair row is this process's)\n");
  // A case validated as it was read comes with its contact rows (Case::contact_rows): its part is
  // cut with them, and not checked again.
  auto stepper = c.contact_rows ? std::make_unique<TimeStepper>(c.problem, whole_mesh_part(c.problem, c.contact_rows),
                                                                la::serial_backend(), c.solvers)
                                : std::make_unique<TimeStepper>(c.problem, c.solvers);
  return make_run(std::move(c), std::move(stepper), o.quiet, std::move(adaptive));
}

std::unique_ptr<Run> set_up_serial(const CaseLoader& load, const RunOptions& o) {
  begin_run(o);
  const SetUpStopsAtOnce at_once;  // a signal ends set-up (meshing, factorizing) at once
  Case c = load({});
  plan_run(c, {.engine = "serial", .petsc_built = o.petsc_built}, o.quiet);  // CHOLMOD, if it fits
  return set_up_on_one_process(std::move(c), o);
}

}  // namespace vpc

namespace vpc {

EngineChoice serial_engine() {
  return {set_up_serial,
          [](std::shared_ptr<const Problem> problem, const SolverChoice& choice) {
            return std::make_unique<TimeStepper>(std::move(problem), choice);
          },
          true, la::Comm{}};
}

}  // namespace vpc
