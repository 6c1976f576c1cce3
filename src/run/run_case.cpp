#include "run/run_case.hpp"

#include "core/error.hpp"
#include "core/stopwatch.hpp"
#include "io/checkpoint.hpp"
#include "io/output_files.hpp"
#include "run/progress.hpp"
#include "scheme/step_failure.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>

namespace vpc {

namespace {

/// Continues from the newest good checkpoint; returns its step.
int resume(Run& e, const RunOptions& o) {
  std::vector<std::string> skipped;
  const auto saved = e.resume(o.resume, skipped);
  // Without a checkpoint to continue, the newest one's reason is the error's (the others' before it).
  if (e.root())
    for (std::size_t i = saved ? 0 : 1; i < skipped.size(); ++i) fmt::print(stderr, "vpcontact: skipping {}\n", skipped[i]);
  if (!saved)
    throw CollectiveError(fmt::format("--resume: no good checkpoint for this case in '{}'{}", o.resume.string(),
                                      skipped.empty()       ? ""
                                      : skipped.size() == 1 ? ": " + skipped.front()
                                                            : fmt::format(": {} (older ones skipped above)", skipped.front())));
  if (!o.quiet && e.root()) {
    fmt::print("  resuming from the checkpoint of step {} (t = {}){}\n", saved->n, saved->t,
               e.ranks() > 0 ? fmt::format(" on {} rank{}", e.ranks(), e.ranks() > 1 ? "s" : "") : "");
    for (const std::string& c : saved->changed) fmt::print("  changed on resume: {}\n", c);
  }
  return saved->n;
}

/// A fresh run: removes an earlier run's files (stale solution_*.vtu, and
/// checkpoints not to resume from), checks that its output fits (check_output_space), writes
/// step 0 and its checkpoint.
void start(Run& e, const RunOptions& o) {
  e.on_root([&] {
    const auto removed = remove_run_outputs(e.directory());
    if (!o.quiet && !removed.empty())
      fmt::print("  removed {} file{} of an earlier run from {}/\n", removed.size(), removed.size() > 1 ? "s" : "",
                 e.directory().string());
  });
  e.check_output_space(0);
  e.start();
  e.checkpoint();
}

/// Where the steps before a failed one are, and how to go on from them.
std::string results_so_far(const Run& e, const RunOptions& o, int done, int last_checkpoint) {
  if (!o.files) return "No output directory";  // RunLoop without an output directory: no files
  return fmt::format("Results up to step {} are in '{}'; `--resume {}` continues from step {}", done,
                     e.directory().string(), shell_quote(e.directory().string()), last_checkpoint);
}

[[noreturn]] void failed_step(const Run& e, const StepReport& r, const RunOptions& o, int last_checkpoint) {
  const bool not_finite = std::isinf(r.contact.residuals.max()) || std::isinf(r.damage.kkt_residual);
  const std::string results = results_so_far(e, o, r.n - 1, last_checkpoint);
  // Which solver failed, with the residual and its value against the tolerance (issue 26: "converged"
  // was printed for a solver whose residual failed); smaller steps only where they can help.
  const double tol = e.tolerance();
  const std::string halve =
      r.contact.pulled_off
          ? " (a pull-off is the end of the bonded body's equilibrium under this load, not a solver's failure: results "
            "up to the step before stand)"
      : !halving_can_help(r, tol)
          ? " (smaller steps cannot help: the contact solver solved this step's problem, and the step size does not "
            "change its residual; another --contact-solver may)"
      : o.halvings == 0 && e.n_steps() > 0 ? " (--retry-halvings N retries a failed step with smaller steps)"
      : e.n_steps() == 0                   ? " (the error control redid it down to dt_min or max_rejections)"
                                           : "";
  throw CollectiveError(fmt::format("step {} (t = {:.6g}) failed{}{}: {} (beta in [{}, {}]). {}{}", r.n, r.t,
                                    o.halvings > 0 ? fmt::format(" after {} step halvings", o.halvings) : "",
                                    not_finite ? " (NaN or Inf in the data of the step: a formula for phi, f0 or f2?)" : "",
                                    step_failure(r, tol), r.beta_min, r.beta_max, results, halve));
}

}  // namespace

void begin_run(const RunOptions& o) {
  if (!o.quiet) fmt::print("{}\n", o.header);
  std::fflush(stdout);
  if (o.output_directory.empty()) return;
  if (!o.resume.empty()) {
    std::error_code ec;
    require(std::filesystem::is_directory(o.output_directory, ec),
            "--resume: no good checkpoint for this case in '{}': {}", o.output_directory.string(),
            ec ? ec.message() : std::string("it is not a directory"));
  }
  prepare_output_directory(o.output_directory);
  remove_temporary_files(o.output_directory);
}

RunResult run_case(const CaseLoader& load, const RunOptions& options, const EngineSetUp& set_up) {
  const std::unique_ptr<Run> engine = set_up(load, options);
  return run_engine(*engine, options);
}

RunResult run_engine(Run& e, const RunOptions& o) {
  RunLoop loop(e, o);
  while (!loop.done()) {
    const StepReport r = loop.step();
    if (const int signal = loop.result().signal; signal && !e.done()) {
      if (e.root()) {
        std::fflush(stdout);
        fmt::print(stderr,
                   "vpcontact: interrupted by {} after step {}{} (t = {:.6g}); checkpoint written in {}/. To "
                   "continue:\n  {}\n",
                   signal_name(signal), r.n, e.n_steps() > 0 ? fmt::format(" of {}", e.n_steps()) : "", r.t,
                   e.directory().string(),
                   resume_command(o.argv, e.directory(), e.ranks()));
      }
      return loop.result();
    }
  }
  loop.finish();
  const RunResult result = loop.result();
  if (!o.quiet && e.root())
    fmt::print("  done in {:.3f} s; results in {}/ (solution.pvd, history.csv, probes.csv, summary.json)\n",
               result.wall_seconds, e.directory().string());
  if (o.after_run) e.on_root([&] { o.after_run(e.directory()); });
  return result;
}

RunLoop::RunLoop(Run& e, const RunOptions& o)
    : engine_(e),
      options_(o),
      schedule_(o.checkpoint_every, o.checkpoint_seconds),
      progress_(e.n_steps(), e.final_time(), o.quiet || !e.root()) {
  if (writes()) {
    e.open_output();
    if (o.resume.empty()) {
      start(e, o);
    } else {
      last_checkpoint_ = resume(e, o);
      e.check_output_space(last_checkpoint_);  // what the rest of the run adds
    }
    schedule_.written();
  }
  result_.steps = last_checkpoint_;
}

StepReport RunLoop::step() {
  Run& e = engine_;
  StepReport r;
  try {
    r = e.step();
  } catch (const Error& stop) {
    // A stop found inside the step (a formula's non-finite value, an unstable explicit step; issue
    // 26), thrown alike on every process: the steps before it stay written, and the message says
    // where, as a failed step's does. No summary.json: the state is the unfinished step's.
    if (e.ranks() > 1 && dynamic_cast<const CollectiveError*>(&stop) == nullptr) throw;
    progress_.finish();
    finished_ = true;  // no further step from the unfinished one
    const std::string what = stop.what();
    throw CollectiveError(fmt::format("{}{} {}", what, what.ends_with('.') ? "" : ".",
                                      results_so_far(e, options_, result_.steps, last_checkpoint_)));
  }
  result_.steps = r.n;
  if (!r.ok) {
    finish();
    failed_step(e, r, options_, last_checkpoint_);
  }
  if (writes()) e.record(r);
  progress_.update(r);
  const int signal = e.interrupt_anywhere();  // stop after this step, on every process
  const bool due = schedule_.by_time() ? e.root_decides(schedule_.due(r.n)) : schedule_.due(r.n);
  if (e.done() || signal || due) checkpoint();
  if (signal && !e.done()) {
    finish();
    result_.signal = signal;
  }
  return r;
}

void RunLoop::checkpoint() {
  if (!writes()) return;
  engine_.checkpoint();
  last_checkpoint_ = result_.steps;
  schedule_.written();
}

void RunLoop::finish() {
  if (finished_) return;
  finished_ = true;
  progress_.finish();
  result_.wall_seconds = seconds_since(options_.started);
  if (!writes()) return;
  engine_.finish(result_.wall_seconds);
  if (engine_.root()) remove_temporary_files(engine_.directory());
}

}  // namespace vpc
