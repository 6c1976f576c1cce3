#pragma once
// The run loop, once for every engine and every caller (the command line, the
// tests, the Python module): set-up, a fresh start or a resume from a
// checkpoint, the steps with their output and progress, checkpoints (at step 0,
// as the schedule says, at the end, when interrupted), summary.json.
//   RunOptions o; o.output_directory = "out";
//   RunResult r = run_case([&](const MeshRequest&) { return load_case("paper-1d"); }, o);
#include "io/case.hpp"
#include "io/checkpoint.hpp"
#include "la/comm.hpp"
#include "run/engine.hpp"
#include "run/progress.hpp"

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace vpc {

/// Builds the case; in a distributed run rank 0 with its mesh, the other ranks without (MeshRequest).
using CaseLoader = std::function<Case(const MeshRequest&)>;

struct RunOptions {
  bool quiet = false;
  std::string header;                       // printed first (unless quiet), e.g. "vpcontact: NAME — description"
  std::filesystem::path output_directory;   // checked before any set-up; empty: no output (a check)
  std::filesystem::path resume;             // non-empty: continue from the newest good checkpoint there
  int halvings = 0;                         // --retry-halvings
  std::string linear_solver{};              // PETSc engine: mumps, cg-gamg, cg-hypre; empty: the default (run/solver_plan.hpp)
  int checkpoint_every = -1;                // steps; -1: by wall time (CheckpointSchedule)
  double checkpoint_seconds = 60;
  std::vector<std::string> argv;            // the command line, for the --resume command after a signal
  std::function<void(const std::filesystem::path&)> after_run;  // on the root, after a complete run (figures)
  bool petsc_built = false;  // the PETSc engine exists (a serial run's refusal names --engine auto)
  /// --engine auto and no --linear-solver: under mpirun, rank 0 runs a small case alone
  /// (plan_solver, SolverRequest::auto_route), and CG + GAMG replaces MUMPS where estimated faster.
  bool auto_route = false;
  bool files = true;  // false: RunLoop only steps (no output, no checkpoints; the Python module without a directory)
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();  // for the wall time
};

struct RunResult {
  int steps = 0;    // the step reached
  int signal = 0;   // the signal that stopped it after a checkpoint (SIGINT, SIGTERM), 0 if it completed
  double wall_seconds = 0;
};

/// Sets up a run on an engine: begin_run, then builds the case and its stepper (assembly,
/// factorization), reporting the stages, and describes them (unless quiet).
/// Throws vpc::Error (Interrupted for a signal during set-up).
using EngineSetUp = std::function<std::unique_ptr<Run>(const CaseLoader&, const RunOptions&)>;

/// A run on the serial engine (TimeStepper over the serial backend: Eigen + CHOLMOD), after
/// the solver plan (run/solver_plan.hpp) has found that CHOLMOD fits.
std::unique_ptr<Run> set_up_serial(const CaseLoader& load, const RunOptions& options);

/// set_up_serial's steps after begin_run and the plan: the stepper of the loaded case `c`; with [adapt],
/// the adapted meshes' steppers made by `adaptive` (empty: on CHOLMOD, as the first).
std::unique_ptr<Run> set_up_on_one_process(Case c, const RunOptions& options, AdaptiveEngine adaptive = {});

struct SolverPlan;
struct SolverRequest;
struct ProblemSize;
/// Chooses the engine and linear solver of the loaded case `c` (plan_solver), reported as
/// a set-up stage and one line (unless quiet). Throws vpc::Error for a run that does not fit.
/// `size`: the problem's sizes where its mesh is not here whole (block_problem_size).
SolverPlan plan_run(const Case& c, const SolverRequest& request, bool quiet, const ProblemSize* size = nullptr);

/// Makes a TimeStepper of a problem with its solver choices: what `converge` runs each
/// level on. Collective on a distributed engine (which distributes rank 0's mesh).
using StepperFactory =
    std::function<std::unique_ptr<TimeStepper>(std::shared_ptr<const Problem>, const SolverChoice&)>;

/// What the commands run on: `run` and `check` set up an engine, `converge` makes the
/// steppers of its levels; `root`: this process reports and writes (rank 0).
struct EngineChoice {
  EngineSetUp set_up;
  StepperFactory make_stepper;
  bool root = true;
  la::Comm comm;  // its processes (one: the serial engine), for the errors every one finds alike
};

/// One process: set_up_serial, TimeStepper(problem, choice).
EngineChoice serial_engine();

/// Before any set-up: prints the header and checks the output directory (--resume
/// needs an existing one; a fresh run's is created; both must be writable).
void begin_run(const RunOptions& options);

/// Runs the case on an engine. Throws vpc::Error for a bad case or option, and
/// vpc::CollectiveError for a step that failed (every process alike).
RunResult run_case(const CaseLoader& load, const RunOptions& options, const EngineSetUp& set_up = set_up_serial);

/// Runs a set-up run: run_case after set-up (a RunLoop to the end).
RunResult run_engine(Run& run, const RunOptions& options);

/// The run loop one step at a time: run_engine runs it to the end, the Python
/// module (python/, docs/python.md) steps it. With RunOptions::files false it
/// only steps: no files, no checkpoints.
class RunLoop {
 public:
  /// Opens the output, then resumes (RunOptions::resume) or starts a fresh run
  /// (step 0 and its checkpoint written). Throws vpc::Error (no checkpoint to resume).
  RunLoop(Run& run, const RunOptions& options);
  bool done() const { return engine_.done(); }
  /// One step, recorded; a checkpoint when due, at the end or after a signal. A
  /// signal (Run::interrupt_anywhere) before the end finishes the run: then
  /// result().signal is set. Throws vpc::CollectiveError for a failed step (after finish()).
  StepReport step();
  /// A checkpoint of the state now (none without an output directory).
  void checkpoint();
  /// The end of a run, complete or not: summary.json written, no temporary file left. Once.
  void finish();
  bool finished() const { return finished_; }
  /// The step of the last checkpoint.
  int last_checkpoint() const { return last_checkpoint_; }
  const RunResult& result() const { return result_; }

 private:
  bool writes() const { return options_.files; }

  Run& engine_;
  RunOptions options_;
  int last_checkpoint_ = 0;
  CheckpointSchedule schedule_;
  Progress progress_;
  RunResult result_;
  bool finished_ = false;
};

}  // namespace vpc
