#include "run/run_case.hpp"

#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "io/output_files.hpp"
#include "run/progress.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>

namespace vpc {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Continues from the newest good checkpoint; returns its step.
int resume(Engine& e, const RunOptions& o) {
  std::vector<std::string> skipped;
  const auto saved = e.resume(o.resume, skipped);
  if (e.root())
    for (const auto& s : skipped) fmt::print(stderr, "vpcontact: skipping {}\n", s);
  if (!saved)
    throw CollectiveError(fmt::format("--resume: no good checkpoint for this case in '{}'{}", o.resume.string(),
                                      skipped.empty() ? "" : " (see the files skipped above)"));
  if (!o.quiet && e.root())
    fmt::print("  resuming from the checkpoint of step {} (t = {}){}\n", saved->n, saved->t,
               e.ranks() > 0 ? fmt::format(" on {} rank{}", e.ranks(), e.ranks() > 1 ? "s" : "") : "");
  return saved->n;
}

/// A fresh run: removes an earlier run's files (stale solution_*.vtu, and
/// checkpoints not to resume from), writes step 0 and its checkpoint.
void start(Engine& e, const RunOptions& o) {
  e.on_root([&] {
    const auto removed = remove_run_outputs(e.directory());
    if (!o.quiet && !removed.empty())
      fmt::print("  removed {} file{} of an earlier run from {}/\n", removed.size(), removed.size() > 1 ? "s" : "",
                 e.directory().string());
  });
  e.start();
  e.checkpoint();
}

[[noreturn]] void failed_step(const Engine& e, const StepReport& r, const RunOptions& o, int last_checkpoint) {
  const bool not_finite = std::isinf(r.contact.residuals.max()) || std::isinf(r.damage.kkt_residual);
  throw CollectiveError(fmt::format(
      "step {} (t = {:.6g}) failed{}{}: contact solver {} after {} iterations (residual {:.2e}), damage solver {} "
      "after {} iterations (KKT residual {:.2e}, beta in [{}, {}]); tolerance {:.1e}. Results up to step {} are in "
      "'{}'; `--resume {}` continues from step {}{}",
      r.n, r.t, o.halvings > 0 ? fmt::format(" after {} step halvings", o.halvings) : "",
      not_finite ? " (NaN or Inf in the data of the step: a formula for phi, f0 or f2?)" : "",
      r.contact.converged ? "converged" : "did not converge", r.contact.iterations, r.contact.residuals.max(),
      r.damage.converged ? "converged" : "did not converge", r.damage.iterations, r.damage.kkt_residual, r.beta_min,
      r.beta_max, e.tolerance(), r.n - 1, e.directory().string(), shell_quote(e.directory().string()), last_checkpoint,
      o.halvings == 0 && e.n_steps() > 0 ? " (--retry-halvings N retries a failed step with smaller steps)"
      : e.n_steps() == 0                 ? " (the error control redid it down to dt_min or max_rejections)"
                                         : ""));
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
  const std::unique_ptr<Engine> engine = set_up(load, options);
  return run_engine(*engine, options);
}

RunResult run_engine(Engine& e, const RunOptions& o) {
  e.open_output();
  int last_checkpoint = o.resume.empty() ? 0 : resume(e, o);
  if (o.resume.empty()) start(e, o);
  CheckpointSchedule schedule(o.checkpoint_every, o.checkpoint_seconds);
  Progress progress(e.n_steps(), e.final_time(), o.quiet || !e.root());
  RunResult result;
  result.steps = last_checkpoint;
  // The end of a run, complete or not: summary.json written, no temporary file left.
  auto finish = [&] {
    progress.finish();
    result.wall_seconds = seconds_since(o.started);
    e.finish(result.wall_seconds);
    if (e.root()) remove_temporary_files(e.directory());
  };
  while (!e.done()) {
    const StepReport r = e.step();
    result.steps = r.n;
    if (!r.ok) {
      finish();
      failed_step(e, r, o, last_checkpoint);
    }
    e.record(r);
    progress.update(r);
    const int signal = e.interrupt_anywhere();  // stop after this step, on every process
    const bool due = schedule.by_time() ? e.root_decides(schedule.due(r.n)) : schedule.due(r.n);
    if (e.done() || signal || due) {
      e.checkpoint();
      last_checkpoint = r.n;
      schedule.written();
    }
    if (signal && !e.done()) {
      finish();
      result.signal = signal;
      if (e.root()) {
        std::fflush(stdout);
        fmt::print(stderr,
                   "vpcontact: interrupted by {} after step {}{} (t = {:.6g}); checkpoint written in {}/. To "
                   "continue:\n  {}\n",
                   signal_name(signal), r.n, e.n_steps() > 0 ? fmt::format(" of {}", e.n_steps()) : "", r.t,
                   e.directory().string(),
                   resume_command(o.argv, e.directory(), e.ranks()));
      }
      return result;
    }
  }
  finish();
  if (!o.quiet && e.root())
    fmt::print("  done in {:.3f} s; results in {}/ (solution.pvd, history.csv, probes.csv, summary.json)\n",
               result.wall_seconds, e.directory().string());
  if (o.after_run) e.on_root([&] { o.after_run(e.directory()); });
  return result;
}

}  // namespace vpc
