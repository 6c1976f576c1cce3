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
#include "core/quote.hpp"
#include "process_policy.hpp"
#include "io/build_info.hpp"
#include "io/case_file.hpp"
#include "la/memory_estimate.hpp"
#include "child_process.hpp"
#include "converge_command.hpp"
#include "figures.hpp"
#include "parallel_run.hpp"
#include "run/progress.hpp"
#include "run/run_case.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace {

namespace fs = std::filesystem;


struct Options {
  std::string case_name = "paper-2d";
  std::string output, outdir;
  std::vector<std::string> sets;
  double kappa = -1, dt = -1;
  int n = -1, steps = -1, every = -1;
  bool no_vtu = false, plot = false;
  vpc::PlotOptions plot_options;
  std::string contact_solver, damage_solver;
  bool spread_pairs = false;  // SolverChoice::spread_pairs
  double tolerance = -1;
  std::string engine = "auto";  // docs/parallel.md
  std::string show_case;        // cases --show NAME
  std::chrono::system_clock::time_point started = std::chrono::system_clock::now();  // for summary.json
  std::string memory_limit;  // la/memory_estimate.hpp
  vpc::RunOptions run;       // quiet, resume, checkpoints, argv (for the --resume command and summary.json), ...
};

/// Whether an option exists on this subcommand and was given.
bool given(const CLI::App& cmd, const std::string& name) {
  const CLI::Option* opt = cmd.get_option_no_throw(name);
  return opt != nullptr && opt->count() > 0;
}

/// The output directory the run will write: --resume, -o, the case's, else output/NAME.
fs::path output_directory(const Options& o, const vpc::CaseInfo& info) {
  if (!o.run.resume.empty()) return o.run.resume;
  if (!o.output.empty()) return o.output;
  if (!info.output_directory.empty()) return info.output_directory;
  return fs::path("output") / info.name;
}

/// The case with the command-line overrides; its output directory is `outdir`.
vpc::Case load_case(const Options& o, const CLI::App& cmd, const vpc::CaseSource& src, const fs::path& outdir,
                    const vpc::MeshRequest& mesh = {}) {
  vpc::CaseOverrides ov{.sets = o.sets, .memory_limit = o.memory_limit};
  if (given(cmd, "--kappa")) ov.kappa = o.kappa;
  if (given(cmd, "--steps")) ov.steps = o.steps;
  if (given(cmd, "--dt")) ov.time_step = o.dt;
  if (given(cmd, "--every")) {
    vpc::require(o.every >= 0, "--every must be >= 0 (got {})", o.every);
    ov.every = o.every;  // a key of the case: read as output.every is (error-controlled steps: docs/cases.md)
  }
  vpc::MeshRequest request = mesh;
  if (given(cmd, "--n")) request.cells = o.n;
  vpc::Case c = vpc::load_case(src, ov, request);
  c.output.directory = outdir;
  c.output.command_line = o.run.argv;
  c.output.started = o.started;
  if (o.no_vtu) c.output.vtu = false;
  if (!o.contact_solver.empty()) c.solvers.contact = o.contact_solver;
  if (!o.damage_solver.empty()) c.solvers.damage = o.damage_solver;
  c.solvers.spread_pairs = o.spread_pairs;
  c.solvers.memory_limit = o.memory_limit;
  if (given(cmd, "--tolerance")) {
    vpc::require(o.tolerance > 0, "--tolerance must be > 0 (got {})", o.tolerance);
    c.solvers.residual_tolerance = o.tolerance;
  }
  return c;
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
  std::fflush(stdout);  // after the stage's line
  for (const auto& w : c.warnings) fmt::print(stderr, "vpcontact: warning: {}\n", w);
  return c;
}

/// The options of the library's run loop (run/run_case.hpp); no output directory: a check.
vpc::RunOptions run_options(const Options& o, const vpc::CaseInfo& info, const fs::path& outdir) {
  vpc::RunOptions r = o.run;
  r.header = fmt::format("vpcontact: {} — {}", vpc::printable(info.name), vpc::printable(info.description, 200));
  r.output_directory = outdir;
#ifdef VPCONTACT_WITH_PETSC
  r.petsc_built = true;
#endif
  r.auto_route = o.engine == "auto" && r.linear_solver.empty();  // mpirun without a choice (set_up_petsc)
  if (o.plot) r.after_run = [p = o.plot_options](const fs::path& dir) { vpc::draw_figures(dir, p, true); };
  return r;
}

/// Runs `task` on the engine --engine chooses (parallel_run.hpp): the PETSc engine under mpirun,
/// with --engine petsc or a --linear-solver; with `auto` on one process, the solver plan
/// (run/solver_plan.hpp) takes CHOLMOD or CG + GAMG once the mesh is built, before set-up.
int on_engine(const Options& o, const vpc::RunOptions& ro, const vpc::EngineTask& task) {
  if (vpc::use_petsc_engine(o.engine) || (o.engine == "auto" && !ro.linear_solver.empty()))
    return vpc::parallel_run(ro, task);
#ifdef VPCONTACT_WITH_PETSC
  if (o.engine == "auto") return vpc::auto_run(task);
#endif
  return task(vpc::serial_engine());
}

/// Builds the case (build_case) for the run loop; in a distributed run rank 0 builds the mesh and reports.
vpc::CaseLoader case_loader(const Options& o, const CLI::App& cmd, const vpc::CaseSource& src, const fs::path& outdir) {
  return [&o, &cmd, &src, outdir](const vpc::MeshRequest& mesh) {
    vpc::StageLog log(o.run.quiet || !mesh.build);
    return build_case(o, cmd, src, outdir, log, mesh);
  };
}

int run(const Options& o, const CLI::App& cmd) {
  vpc::require(o.run.halvings >= 0 && o.run.halvings <= 20, "--retry-halvings must be in [0, 20] (got {})",
               o.run.halvings);
  const vpc::CaseSource src = vpc::case_source(o.case_name);
  const vpc::CaseInfo info = header_info(o, src);
  const fs::path outdir = output_directory(o, info);
  const vpc::RunOptions ro = run_options(o, info, outdir);
  return on_engine(o, ro, [&](const vpc::EngineChoice& engine) {
    const vpc::RunResult r = vpc::run_case(case_loader(o, cmd, src, outdir), ro, engine.set_up);
    return r.signal ? 128 + r.signal : 0;
  });
}

/// Set-up (parse, mesh, assemble, factorize) without a run.
int check(const Options& o, const CLI::App& cmd) {
  const vpc::CaseSource src = vpc::case_source(o.case_name);
  const vpc::CaseInfo info = header_info(o, src);
  const vpc::RunOptions ro = run_options(o, info, {});
  return on_engine(o, ro, [&](const vpc::EngineChoice& choice) {
    const auto engine = choice.set_up(case_loader(o, cmd, src, output_directory(o, info)), ro);
    const std::string output = engine->check_output_space(0);  // refused where a run's output would not fit
    if (engine->root() && !o.run.quiet) fmt::print("  {}\n", output);
    if (engine->root()) fmt::print("{}: ok\n", o.case_name);
    return 0;
  });
}

/// "  paper-2d        description" for each built-in case, the descriptions in one column.
std::string builtin_case_list() {
  std::size_t width = 0;
  for (const auto& s : vpc::shipped_cases()) width = std::max(width, s.name.size());
  std::string list;
  for (const auto& s : vpc::shipped_cases())
    list += fmt::format("  {:{}} {}\n", s.name, width, vpc::case_description(s.text));
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
                  "keys it excludes (time.steps/dt, output.every/times, damage.phi/source, mesh.file/generator); "
                  "obstacle[0].radius=0.5 sets a key of the first [[obstacle]]; 'damage={kappa=0.5}' sets those keys "
                  "only; a new viscoplasticity.law drops the old law's parameters");
  cmd->add_option("--kappa", o.kappa, "damage diffusion kappa (>= 0)");
  cmd->add_option("-n,--n", o.n,
                  "generated meshes only: n cells along every edge, whatever the domain's aspect (1D: n segments; 2D: n x n "
                  "cells; 3D: n^3 boxes)");
  cmd->add_option("--steps", o.steps, "number of time steps N (k = T / N)");
  cmd->add_option("--dt", o.dt, "time step k (must divide T)");
  cmd->add_option("--contact-solver", o.contact_solver,
                  "auto (default: the dual active set for few contact nodes and a direct solver, else the primal), "
                  "active-set, primal-active-set or penalty-duality")
      ->check(CLI::IsMember(vpc::kContactSolverNames));
  cmd->add_option("--damage-solver", o.damage_solver, "active-set (default) or penalty-duality")
      ->check(CLI::IsMember({"active-set", "penalty-duality"}));
  cmd->add_option("--tolerance", o.tolerance, "largest relative KKT residual accepted at a step (default 1e-8)");
  cmd->add_option("--memory-limit", o.memory_limit,
                  "refuse a run estimated to need more memory, e.g. 8G (default: $VPCONTACT_MEMORY_LIMIT, else the "
                  "memory available; 'unlimited': no check); also what meshing a .geo may take");
  cmd->add_option("--engine", o.engine, "auto (PETSc under mpirun or with --linear-solver, if built with it; else one process: "
                  "CHOLMOD, or CG + GAMG when CHOLMOD's factors would not fit in memory or CG + GAMG is estimated to "
                  "be faster; chosen before set-up and printed), serial or petsc");
  cmd->add_option("--linear-solver", o.run.linear_solver, "PETSc engine: mumps (default; CG + GAMG instead, saying so, "
                  "where MUMPS's factors would not fit in memory), cg-gamg or cg-hypre");
  cmd->add_flag("--spread-pairs", o.spread_pairs,
               "PETSc engine: spread each contact pair's rows over the ranks (a row goes with its slave node's owner, its "
               "master nodes, and a large-sliding pair's whole master side, become ghosts there) instead of owning "
               "each pair's nodes together (a large-sliding pair's on rank 0); "
               "the dual contact solver (active-set) alone solves such rows, auto takes it; nothing to spread on one "
               "process");
  cmd->add_flag("-q,--quiet", o.run.quiet, "print nothing but errors");
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
  o.run.argv.assign(argv, argv + argc);

  auto* run_cmd = app.add_subcommand("run", "run a case (default: paper-2d)");
  add_case_options(run_cmd, o);
  run_cmd->add_option("-o,--output", o.output, "output directory (default: the case's, else output/CASE)");
  run_cmd->add_option("--every", o.every, "write VTU every this many steps (0: final step only)");
  run_cmd->add_flag("--no-vtu", o.no_vtu, "write no VTU/PVD files (CSV and summary only)");
  run_cmd->add_flag("--plot", o.plot,
                    "draw the figures (vpcontact plot) after the run; without python3-matplotlib only a warning");
  add_plot_options(run_cmd, o);
  run_cmd->add_option("--checkpoint-every", o.run.checkpoint_every,
                      "write a checkpoint every this many steps (0: only at the start and the end; default: by time, "
                      "see --checkpoint-seconds)")
      // -1, the default's "by time", is not a value to give: a negative count is a mistake.
      ->check(CLI::Validator(
          [](std::string& v) {
            return !v.empty() && v[0] == '-' ? "expected a number of steps >= 0 (0: only at the start and the end), got " + v
                                             : std::string();
          },
          "N >= 0"));
  run_cmd->add_option("--checkpoint-seconds", o.run.checkpoint_seconds,
                      "without --checkpoint-every: write a checkpoint once this many seconds of wall time have passed "
                      "since the last one (default 60)");
  run_cmd->add_option("--resume", o.run.resume,
                      "continue an interrupted run of the same case from the newest good checkpoint in this directory");
  run_cmd->add_option("--retry-halvings", o.run.halvings,
                      "retry a failed step as two half steps, at most this many times nested (default 0)");
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
    // One line, no terminal controls, whatever user text a message echoes (each echo is bounded too).
    fmt::print(stderr, "vpcontact: error: {}\n", vpc::printable(e.what(), 2000));
    return 1;
  } catch (const std::bad_alloc&) {
    std::fflush(stdout);
    fmt::print(stderr, "vpcontact: error: out of memory (an allocation failed: the machine's memory, or a limit such "
                       "as ulimit -v, was reached); use a coarser mesh or more memory (--memory-limit checks a run "
                       "against a limit before it factorizes)\n");
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "vpcontact: internal error: {}\n", e.what());
    return 2;
  }
}
