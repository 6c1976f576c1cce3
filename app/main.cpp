// vpcontact: the command line on the library.
//   vpcontact run [CASE] [options]   run a built-in case or a case file (default: paper-2d)
//   vpcontact check CASE             validate a case without running it
//   vpcontact cases [--show NAME]    list the built-in cases, or print one's TOML
//   vpcontact plot OUTDIR            draw the figures of a run's output
//   vpcontact --version
// Every error is one line `vpcontact: error: ...` and exit code 1; a run stopped
// by SIGINT/SIGTERM exits with 130/143 after writing a checkpoint.
#include "cases/builtin_cases.hpp"
#include "cases/shipped_cases.hpp"
#include "core/error.hpp"
#include "core/malloc_policy.hpp"
#include "core/omp_wait_policy.hpp"
#include "io/build_info.hpp"
#include "io/case_file.hpp"
#include "io/checkpoint.hpp"
#include "io/output_files.hpp"
#include "io/run_output.hpp"
#include "child_process.hpp"
#include "converge_command.hpp"
#include "figures.hpp"
#include "interrupt.hpp"
#include "parallel_run.hpp"
#include "progress.hpp"
#include "scheme/time_stepper.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;


struct Options {
  std::string case_name = "paper-2d";
  std::string output, outdir;
  std::vector<std::string> sets;
  double kappa = -1, dt = -1;
  int n = -1, steps = -1, every = -1, checkpoint_every = -1, halvings = 0;
  double checkpoint_seconds = 60;
  bool no_vtu = false, quiet = false, plot = false;
  vpc::PlotOptions plot_options;
  std::string resume;
  std::string contact_solver, damage_solver;
  double tolerance = -1;
  std::string engine = "auto", linear_solver = "mumps";  // docs/parallel.md
  std::string show_case;                                 // cases --show NAME
  std::vector<std::string> argv;  // for the --resume command and summary.json
  std::chrono::system_clock::time_point started = std::chrono::system_clock::now();  // for summary.json
  std::string memory_limit;  // solvers/memory_estimate.hpp
};

/// Whether an option exists on this subcommand and was given.
bool given(const CLI::App& cmd, const std::string& name) {
  const CLI::Option* opt = cmd.get_option_no_throw(name);
  return opt != nullptr && opt->count() > 0;
}

/// The output directory the run will write: --resume, -o, the case's, else output/NAME.
fs::path output_directory(const Options& o, const vpc::CaseInfo& info) {
  if (!o.resume.empty()) return o.resume;
  if (!o.output.empty()) return o.output;
  if (!info.output_directory.empty()) return info.output_directory;
  return fs::path("output") / info.name;
}

/// The case with the command-line overrides; its output directory is `outdir`.
vpc::Case load_case(const Options& o, const CLI::App& cmd, const vpc::CaseSource& src, const fs::path& outdir,
                    const vpc::MeshRequest& mesh = {}) {
  vpc::CaseOverrides ov{.sets = o.sets};
  if (given(cmd, "--kappa")) ov.kappa = o.kappa;
  if (given(cmd, "--steps")) ov.steps = o.steps;
  if (given(cmd, "--dt")) ov.time_step = o.dt;
  vpc::MeshRequest request = mesh;
  if (given(cmd, "--n")) {
    vpc::require(o.n >= 1, "--n must be >= 1 (got {})", o.n);
    request.cells = o.n;
  }
  vpc::Case c = vpc::load_case(src, ov, request);
  c.output.directory = outdir;
  c.output.command_line = o.argv;
  c.output.started = o.started;
  if (given(cmd, "--every")) {
    vpc::require(o.every >= 0, "--every must be >= 0 (got {})", o.every);
    c.output.every = o.every;
    c.output.times.clear();
  }
  if (o.no_vtu) c.output.vtu = false;
  if (!o.contact_solver.empty()) c.solvers.contact = o.contact_solver;
  if (!o.damage_solver.empty()) c.solvers.damage = o.damage_solver;
  c.solvers.memory_limit = o.memory_limit;
  if (given(cmd, "--tolerance")) {
    vpc::require(o.tolerance > 0, "--tolerance must be > 0 (got {})", o.tolerance);
    c.solvers.residual_tolerance = o.tolerance;
  }
  return c;
}

/// The first thing printed, before any set-up: the case's name and description.
void print_header(const vpc::CaseInfo& info, bool quiet) {
  if (quiet) return;
  fmt::print("vpcontact: {} — {}\n", info.name, info.description);
  std::fflush(stdout);
}

/// The case header's name and description, as the case will give them.
vpc::CaseInfo header_info(const Options& o, const vpc::CaseSource& src) {
  vpc::CaseInfo info = vpc::case_info(src.text, src.name, {.sets = o.sets});
  if (src.builtin) info.name = o.case_name;
  return info;
}

/// Builds the case, reported as the first set-up stage.
vpc::Case build_case(const Options& o, const CLI::App& cmd, const vpc::CaseSource& src, const fs::path& outdir,
                     vpc::StageLog& log, const vpc::MeshRequest& mesh = {}) {
  const auto t = std::chrono::steady_clock::now();
  log(vpc::is_case_file(o.case_name) ? fmt::format("reading {} and building the mesh", o.case_name)
                                : std::string("building the mesh"),
      -1);
  vpc::Case c = load_case(o, cmd, src, outdir, mesh);
  log("", std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
  return c;
}

/// What set-up found, after the stages.
void describe(const vpc::Case& c, const vpc::TimeStepper& stepper) {
  const auto& p = stepper.problem();
  const auto [hmin, hmax] = p.mesh.size_range();
  fmt::print("  mesh: d = {}, {} nodes, {} cells, h in [{:.3g}, {:.3g}]; {} free displacement dofs, {} contact nodes\n",
             p.mesh.dim(), p.mesh.n_nodes(), p.mesh.n_cells(), hmin, hmax, stepper.dofs().n_free(),
             stepper.contact_nodes().size());
  fmt::print("  Γ1 (clamped): {}; Γ3 (contact): {}\n", fmt::join(p.clamped, ", "), fmt::join(p.contact.parts, ", "));
  fmt::print("  elasticity: {} (E = {}, nu = {}); G: {}; phi: {}\n", p.elasticity.name(), p.elasticity.young(),
             p.elasticity.poisson(), p.law->describe(), p.source->describe());
  fmt::print("  kappa = {}; T = {}, k = {}, N = {}; solvers: contact {}, damage {}; setup {:.3f} s\n", p.kappa,
             p.final_time, p.step(), p.n_steps, c.solvers.contact, c.solvers.damage, stepper.setup_seconds());
}

/// Checks the output directory before any set-up: --resume needs an existing
/// one; a fresh run's is created; both must be writable.
void check_output_directory(const Options& o, const fs::path& dir) {
  if (!o.resume.empty()) {
    std::error_code ec;
    vpc::require(fs::is_directory(dir, ec), "--resume: no good checkpoint for this case in '{}': {}", dir.string(),
                 ec ? ec.message() : std::string("it is not a directory"));
  }
  vpc::prepare_output_directory(dir);
  vpc::remove_temporary_files(dir);
}

void remove_earlier_outputs(const fs::path& dir, bool quiet) {
  const auto removed = vpc::remove_run_outputs(dir);
  if (!quiet && !removed.empty())
    fmt::print("  removed {} file{} of an earlier run from {}/\n", removed.size(), removed.size() > 1 ? "s" : "",
               dir.string());
}

int interrupted_exit(const vpc::StepReport& r, int n_steps, const fs::path& dir, const Options& o, int mpi_size) {
  std::fflush(stdout);
  fmt::print(stderr,
             "vpcontact: interrupted by {} after step {} of {} (t = {:.6g}); checkpoint written in {}/. To continue:\n"
             "  {}\n",
             vpc::signal_name(vpc::interrupt_signal()), r.n, n_steps, r.t, dir.string(),
             vpc::resume_command(o.argv, dir, mpi_size));
  return 128 + vpc::interrupt_signal();
}

int run(const Options& o, const CLI::App& cmd) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  vpc::require(o.halvings >= 0 && o.halvings <= 20, "--retry-halvings must be in [0, 20] (got {})", o.halvings);
  const vpc::CaseSource src = vpc::case_source(o.case_name);
  const vpc::CaseInfo info = header_info(o, src);
  const fs::path outdir = output_directory(o, info);
  if (vpc::use_petsc_engine(o.engine)) {  // mpirun -np P vpcontact run CASE (docs/parallel.md)
    vpc::ParallelRunOptions po;
    po.quiet = o.quiet;
    po.resume = o.resume;
    po.halvings = o.halvings;
    po.linear_solver = o.linear_solver;
    po.plot = o.plot;
    po.checkpoint_every = o.checkpoint_every;
    po.checkpoint_seconds = o.checkpoint_seconds;
    po.header = fmt::format("vpcontact: {} — {}", info.name, info.description);
    po.output_directory = outdir;
    po.argv = o.argv;
    po.plot_options = o.plot_options;
    return vpc::parallel_run(
        [&](const vpc::MeshRequest& mesh) {
          vpc::StageLog log(o.quiet || !mesh.build);  // rank 0 builds the mesh and reports
          return build_case(o, cmd, src, outdir, log, mesh);
        },
        po);
  }
  print_header(info, o.quiet);
  check_output_directory(o, outdir);
  vpc::stop_if_interrupted();
  vpc::StageLog log(o.quiet);
  vpc::Case c = build_case(o, cmd, src, outdir, log);
  c.solvers.max_halvings = o.halvings;
  c.solvers.on_setup_stage = [&](const std::string& stage, double seconds) {
    log(stage, seconds);
    if (seconds >= 0) vpc::stop_if_interrupted();
  };
  vpc::TimeStepper stepper(c.problem, c.solvers);
  if (!o.quiet) describe(c, stepper);
  vpc::RunOutput output(stepper, c.output);
  const std::uint64_t fingerprint = vpc::problem_fingerprint(stepper);
  auto checkpoint = [&] {
    vpc::write_checkpoint(output.directory(), {c.name, fingerprint, stepper.snapshot(), output.pvd_entries(),
                                               output.totals()});
  };
  int last_checkpoint = 0;
  if (!o.resume.empty()) {
    std::vector<std::string> skipped;
    auto saved = vpc::find_checkpoint(o.resume, fingerprint, &skipped);
    for (const auto& s : skipped) fmt::print(stderr, "vpcontact: skipping {}\n", s);
    vpc::require(saved.has_value(), "--resume: no good checkpoint for this case in '{}'{}", o.resume,
                 skipped.empty() ? "" : " (see the files skipped above)");
    stepper.restore(saved->snapshot);
    output.resume(saved->snapshot.state.n, saved->pvd, saved->totals);
    last_checkpoint = saved->snapshot.state.n;
    if (!o.quiet)
      fmt::print("  resuming from the checkpoint of step {} (t = {})\n", last_checkpoint, saved->snapshot.state.t);
  } else {
    remove_earlier_outputs(outdir, o.quiet);  // stale solution_*.vtu, and checkpoints not to resume from
    output.start();
    checkpoint();
  }
  // Checkpoints: at step 0, at the end, when interrupted, and as the schedule says (by default by time).
  vpc::CheckpointSchedule schedule(o.checkpoint_every, o.checkpoint_seconds);
  vpc::Progress progress(c.problem->n_steps, o.quiet);
  while (!stepper.done()) {
    const vpc::StepReport r = stepper.step();
    if (!r.ok) {
      progress.finish();
      output.finish(std::chrono::duration<double>(Clock::now() - t0).count());
      vpc::remove_temporary_files(outdir);
      const bool not_finite = std::isinf(r.contact.residuals.max()) || std::isinf(r.damage.kkt_residual);
      vpc::fail("step {} (t = {:.6g}) failed{}{}: contact solver {} after {} iterations (residual {:.2e}), damage solver {} "
                "after {} iterations (KKT residual {:.2e}, beta in [{}, {}]); tolerance {:.1e}. Results up to step {} "
                "are in '{}'; `--resume {}` continues from step {}{}",
                r.n, r.t, o.halvings > 0 ? fmt::format(" after {} step halvings", o.halvings) : "",
                not_finite ? " (NaN or Inf in the data of the step: a formula for phi, f0 or f2?)" : "",
                r.contact.converged ? "converged" : "did not converge", r.contact.iterations,
                r.contact.residuals.max(), r.damage.converged ? "converged" : "did not converge",
                r.damage.iterations, r.damage.kkt_residual, r.beta_min, r.beta_max, c.solvers.residual_tolerance,
                r.n - 1, output.directory().string(), vpc::shell_quote(output.directory().string()), last_checkpoint,
                o.halvings == 0 ? " (--retry-halvings N retries a failed step with smaller steps)" : "");
    }
    output.record(r);
    progress.update(r);
    const bool interrupted = vpc::interrupt_signal() != 0;
    if (stepper.done() || interrupted || schedule.due(r.n)) {
      checkpoint();
      last_checkpoint = r.n;
      schedule.written();
    }
    if (interrupted && !stepper.done()) {
      progress.finish();
      output.finish(std::chrono::duration<double>(Clock::now() - t0).count());
      vpc::remove_temporary_files(outdir);
      return interrupted_exit(r, c.problem->n_steps, outdir, o, 0);
    }
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  output.finish(wall);
  vpc::remove_temporary_files(outdir);
  if (!o.quiet)
    fmt::print("  done in {:.3f} s; results in {}/ (solution.pvd, history.csv, probes.csv, summary.json)\n", wall,
               output.directory().string());
  if (o.plot) vpc::draw_figures(outdir, o.plot_options, true);
  return 0;
}

int check(const Options& o, const CLI::App& cmd) {
  const vpc::CaseSource src = vpc::case_source(o.case_name);
  const vpc::CaseInfo info = header_info(o, src);
  print_header(info, o.quiet);
  vpc::StageLog log(o.quiet);
  vpc::Case c = build_case(o, cmd, src, output_directory(o, info), log);
  c.solvers.on_setup_stage = std::ref(log);
  vpc::TimeStepper stepper(c.problem, c.solvers);  // validates, assembles, factorizes
  if (!o.quiet) describe(c, stepper);
  fmt::print("{}: ok\n", o.case_name);
  return 0;
}

/// "  paper-2d   description" for each built-in case.
std::string builtin_case_list() {
  std::string list;
  for (const auto& s : vpc::shipped_cases()) list += fmt::format("  {:10} {}\n", s.name, vpc::case_description(s.text));
  return list;
}

int cases(const Options& o) {
  if (!o.show_case.empty()) {
    fmt::print("{}", vpc::case_source(o.show_case).text);
    return 0;
  }
  fmt::print("{}", builtin_case_list());
  fmt::print("(each is shipped as cases/<name>.toml, a starting point for your own cases: vpcontact cases --show NAME "
             "prints it)\n");
  return 0;
}

void add_case_options(CLI::App* cmd, Options& o) {
  cmd->add_option("case", o.case_name, "a case file (.toml) or a built-in case (listed below)")->capture_default_str();
  cmd->footer("Built-in cases (vpcontact cases --show NAME prints one's TOML):\n" + builtin_case_list());
  cmd->add_option("--set", o.sets,
                  "override a case-file key, e.g. --set damage.kappa=0.1 (repeatable); a key replaces the file's "
                  "keys it excludes (time.steps/dt, output.every/times, damage.phi/source, mesh.file/generator)");
  cmd->add_option("--kappa", o.kappa, "damage diffusion kappa (>= 0)");
  cmd->add_option("-n,--n", o.n,
                  "generated meshes only: cells per edge (1D: segments; 2D: n x n squares; 3D: n^3 cubes)");
  cmd->add_option("--steps", o.steps, "number of time steps N (k = T / N)");
  cmd->add_option("--dt", o.dt, "time step k (must divide T)");
  cmd->add_option("--contact-solver", o.contact_solver, "active-set (default) or penalty-duality")
      ->check(CLI::IsMember({"active-set", "penalty-duality"}));
  cmd->add_option("--damage-solver", o.damage_solver, "active-set (default) or penalty-duality")
      ->check(CLI::IsMember({"active-set", "penalty-duality"}));
  cmd->add_option("--tolerance", o.tolerance, "largest relative KKT residual accepted at a step (default 1e-8)");
  cmd->add_option("--memory-limit", o.memory_limit,
                  "refuse a run estimated to need more memory, e.g. 8G (default: $VPCONTACT_MEMORY_LIMIT, else the "
                  "memory available; 'unlimited': no check)");
  cmd->add_flag("-q,--quiet", o.quiet, "print nothing but errors");
}

void add_plot_options(CLI::App* cmd, Options& o) {
  cmd->add_option("--format", o.plot_options.format, "figure format: png (default), pdf or svg")
      ->check(CLI::IsMember({"png", "pdf", "svg"}));
  cmd->add_option("--dpi", o.plot_options.dpi, "figure resolution in dots per inch (default 150)")
      ->check(CLI::Range(1.0, 2400.0));
}

/// A command-line error on one line (CLI11's messages may span several).
std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  vpc::ensure_passive_omp_wait(argv);
  vpc::keep_freed_memory();
  CLI::App app{"vpcontact: quasistatic frictionless Signorini contact of elastic-viscoplastic bodies with damage\n"
               "(the fully discrete scheme of Fernandez & Sofonea, 2003)",
               "vpcontact"};
  app.require_subcommand(0, 1);
  app.set_version_flag(
      "--version", [] { return fmt::format("vpcontact {} (git {})", vpc::version(), vpc::git_commit()); },
      "print the version and exit");
  Options o;
  o.argv.assign(argv, argv + argc);

  auto* run_cmd = app.add_subcommand("run", "run a case (default: paper-2d)");
  add_case_options(run_cmd, o);
  run_cmd->add_option("-o,--output", o.output, "output directory (default: the case's, else output/CASE)");
  run_cmd->add_option("--every", o.every, "write VTU every this many steps (0: final step only)");
  run_cmd->add_flag("--no-vtu", o.no_vtu, "write no VTU/PVD files (CSV and summary only)");
  run_cmd->add_flag("--plot", o.plot,
                    "draw the figures (vpcontact plot) after the run; without python3-matplotlib only a warning");
  add_plot_options(run_cmd, o);
  run_cmd->add_option("--checkpoint-every", o.checkpoint_every,
                      "write a checkpoint every this many steps (0: only at the start and the end; default: by time, "
                      "see --checkpoint-seconds)");
  run_cmd->add_option("--checkpoint-seconds", o.checkpoint_seconds,
                      "without --checkpoint-every: write a checkpoint once this many seconds of wall time have passed "
                      "since the last one (default 60)");
  run_cmd->add_option("--resume", o.resume,
                      "continue an interrupted run of the same case from the newest good checkpoint in this directory");
  run_cmd->add_option("--retry-halvings", o.halvings,
                      "retry a failed step as two half steps, at most this many times nested (default 0)");

  run_cmd->add_option("--engine", o.engine, "auto (PETSc under mpirun, if built with it), serial or petsc");
  run_cmd->add_option("--linear-solver", o.linear_solver, "PETSc engine: mumps (default), cg-gamg or cg-hypre");
  auto* check_cmd = app.add_subcommand("check", "validate a case (parse, mesh, assemble, factorize) without running it");
  add_case_options(check_cmd, o);
  auto* cases_cmd = app.add_subcommand("cases", "list the built-in cases");
  cases_cmd->add_option("--show", o.show_case, "print the TOML of this built-in case (a start for your own)");
  auto* plot_cmd = app.add_subcommand("plot", "draw the paper's figures from a run's output directory");
  plot_cmd->add_option("outdir", o.outdir, "the output directory of a run")->required();
  add_plot_options(plot_cmd, o);
  auto* converge_cmd = vpc::add_converge_command(app);

  if (argc == 1) {  // `vpcontact` alone: what it can do (`vpcontact run` runs paper-2d)
    fmt::print("{}", app.help());
    return 0;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "vpcontact: error: {} (see vpcontact --help)\n", one_line(e.what()));
    return 1;
  }
  try {
    if (*cases_cmd) return cases(o);
    if (*plot_cmd) {
      vpc::draw_figures(o.outdir, o.plot_options, false);
      return 0;
    }
    if (*converge_cmd) return vpc::run_converge_command();
    if (*check_cmd) {
      vpc::catch_interrupts();
      return check(o, *check_cmd);
    }
    if (*run_cmd) {
      vpc::catch_interrupts();
      return run(o, *run_cmd);
    }
    fmt::print("{}", app.help());  // options of the program only (e.g. none but --version): the help
    return 0;
  } catch (const vpc::Interrupted& e) {
    std::fflush(stdout);
    fmt::print(stderr, "\nvpcontact: {}\n", e.what());
    return 128 + e.signal;
  } catch (const vpc::Error& e) {
    std::fflush(stdout);
    fmt::print(stderr, "vpcontact: error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "vpcontact: internal error: {}\n", e.what());
    return 2;
  }
}
