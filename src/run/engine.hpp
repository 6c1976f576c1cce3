#pragma once
// What the run loop (run/run_case.hpp) needs of an engine: a stepper, its output
// and its checkpoints. make_run builds the one implementation (TimeStepper,
// RunOutput, io/checkpoint) on one process or on many (parallel/petsc_engine.hpp
// sets that up); every call is collective and returns the same on every process.
#include "run/interrupt.hpp"
#include "scheme/time_stepper.hpp"

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vpc {

/// Where a resumed run continues: the step and time of its checkpoint, and the keys of the
/// case that changed since (those that may: "time.T: 1 → 2"; on the root).
struct ResumedAt {
  int n = 0;
  double t = 0;
  std::vector<std::string> changed;
};

class Run {
 public:
  virtual ~Run() = default;

  // The scheme.
  virtual bool done() const = 0;
  virtual StepReport step() = 0;
  /// N of a fixed grid; 0 for error-controlled steps.
  virtual int n_steps() const = 0;
  virtual double final_time() const = 0;
  /// The largest relative residual a step accepts (SolverChoice::residual_tolerance).
  virtual double tolerance() const = 0;

  // Output (the output directory of the case) and checkpoints.
  /// Opens the output (locates the probes); before start() or resume().
  virtual void open_output() = 0;
  virtual const std::filesystem::path& directory() const = 0;
  /// A fresh run: writes step 0.
  virtual void start() = 0;
  virtual void record(const StepReport& r) = 0;
  /// Writes summary.json; `wall_seconds`: the whole run's time.
  virtual void finish(double wall_seconds) = 0;
  virtual void checkpoint() = 0;
  /// Restores the newest good checkpoint for this problem in `dir` and continues
  /// the output from it; nullopt if there is none (`skipped` says why, per file).
  virtual std::optional<ResumedAt> resume(const std::filesystem::path& dir, std::vector<std::string>& skipped) = 0;
  /// The size of the output from step `from` to the end against the free space where the
  /// output directory is (run/output_space.hpp): throws vpc::CollectiveError where it does
  /// not fit, warns (on stderr) where it takes more than half of it; returns a line that says
  /// both (on the root; "" for an engine without output).
  virtual std::string check_output_space(int /*from*/) { return {}; }

  // The processes (one, for the serial engine).
  /// The process that prints and writes the shared files.
  virtual bool root() const { return true; }
  /// The MPI ranks, for the resume command (`mpirun -np P`); 0 when not under MPI.
  virtual int ranks() const { return 0; }
  /// The signal any process has received (interrupt_signal()), the same everywhere.
  virtual int interrupt_anywhere() const { return interrupt_signal(); }
  /// Rank 0's `value`, everywhere (a decision on one clock).
  virtual bool root_decides(bool value) const { return value; }
  /// Runs `work` on the root only; its error (vpc::CollectiveError) is every process's.
  virtual void on_root(const std::function<void()>& work) { work(); }

  /// The stepper (its state, mesh and matrices, for the Python module's views); null
  /// for an engine without one (a test's scripted engine). An adaptive run ([adapt]) replaces it
  /// at each adaptation: ask again after a step.
  virtual const TimeStepper* stepper() const { return nullptr; }
  /// Called with a stepper just before an adaptation destroys it (its state may be taken:
  /// TimeStepper::take_state); empty: none. Called inside step(), on the stepping thread.
  virtual void on_retire(std::function<void(TimeStepper&)> /*hook*/) {}
};

struct Case;  // io/case.hpp

/// With [adapt] (Case::adapt), the engine's way to make a stepper of an adapted mesh and the problem
/// on its coarse mesh (the PETSc engine's case keeps no mesh once cut); empty: the serial engine's,
/// and the case's problem.
struct AdaptiveEngine {
  std::function<std::unique_ptr<TimeStepper>(std::shared_ptr<const Problem>, const SolverChoice&)> make;
  std::shared_ptr<const Problem> coarse;
  /// How each adapted mesh's engine and linear solver are chosen, for the [adapt] line of the run's header
  /// (empty: on CHOLMOD, as the first mesh).
  std::string plan;
};

/// The engine over `stepper` (one process, or this process's part), its output
/// and checkpoints, for the case `c`; unless quiet, rank 0 prints what set-up
/// found. Collective.
std::unique_ptr<Run> make_run(Case c, std::unique_ptr<TimeStepper> stepper, bool quiet, AdaptiveEngine adaptive = {});

/// The lines of an engine's description that come from the case: boundary
/// parts, material, damage, time and solvers, and the set-up time.
void describe_data(const Problem& problem, const SolverChoice& solvers, double setup_seconds);

}  // namespace vpc
