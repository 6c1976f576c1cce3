// vpcontact: the command line on the library.
//   vpcontact run [CASE] [options]   run a built-in case or a case file (default: paper-2d)
//   vpcontact check CASE             validate a case without running it
//   vpcontact cases                  list the built-in cases
//   vpcontact plot OUTDIR            draw the figures of a run's output
#include "cases/builtin_cases.hpp"
#include "cases/shipped_cases.hpp"
#include "core/error.hpp"
#include "core/malloc_policy.hpp"
#include "core/omp_wait_policy.hpp"
#include "io/case_file.hpp"
#include "io/checkpoint.hpp"
#include "io/run_output.hpp"
#include "converge_command.hpp"
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
  std::string resume;
  std::string contact_solver, damage_solver;
  double tolerance = -1;
  std::string engine = "auto", linear_solver = "mumps";  // docs/parallel.md
  std::string memory_limit;  // solvers/memory_estimate.hpp
};

/// Whether an option exists on this subcommand and was given.
bool given(const CLI::App& cmd, const std::string& name) {
  const CLI::Option* opt = cmd.get_option_no_throw(name);
  return opt != nullptr && opt->count() > 0;
}

bool is_case_file(const std::string& s) {
  return s.size() > 5 && (s.ends_with(".toml") || fs::is_regular_file(s));
}

/// The case named on the command line: a case file, or a built-in case (its
/// compiled-in TOML twin when --set is used), with the command-line overrides.
vpc::Case load_case(const Options& o, const CLI::App& cmd, const vpc::MeshRequest& mesh = {}) {
  vpc::CaseOverrides ov;
  ov.build_mesh = mesh.build;
  if (given(cmd, "--kappa")) ov.kappa = o.kappa;
  if (given(cmd, "--steps")) ov.steps = o.steps;
  if (given(cmd, "--dt")) ov.time_step = o.dt;
  vpc::Case c;
  const bool builtin_name = !is_case_file(o.case_name);
  const auto& builtins = vpc::builtin_case_names();
  const bool has_cpp_builtin = std::find(builtins.begin(), builtins.end(), o.case_name) != builtins.end();
  if (builtin_name && has_cpp_builtin && o.sets.empty()) {
    if (given(cmd, "--n")) ov.mesh_cells = o.n;
    c = vpc::make_builtin_case(o.case_name, ov);
  } else {
    std::vector<std::string> sets = o.sets;
    if (given(cmd, "--n")) sets.insert(sets.begin(), fmt::format("mesh.cells={}", o.n));
    if (builtin_name) {
      const auto& shipped = vpc::shipped_cases();
      auto it = std::find_if(shipped.begin(), shipped.end(), [&](const auto& s) { return s.name == o.case_name; });
      if (it == shipped.end()) {
        std::vector<std::string> names;
        for (const auto& s : shipped) names.emplace_back(s.name);
        vpc::fail("unknown case '{}'; built-in cases are: {} (or give a case file, NAME.toml)", o.case_name,
                  fmt::join(names, ", "));
      }
      // Shipped cases find their meshes (cases/meshes/) in the source tree.
      c = vpc::parse_case(it->text, std::string(it->name) + ".toml (built-in)", fs::path(VPC_SOURCE_DIR) / "cases",
                          sets, mesh);
    } else {
      c = vpc::read_case_file(o.case_name, sets, mesh);
    }
    vpc::apply_case_overrides(*c.problem, ov);
  }
  if (!o.output.empty()) c.output.directory = o.output;
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

void describe(const vpc::Case& c, const vpc::TimeStepper& stepper) {
  const auto& p = stepper.problem();
  const auto [hmin, hmax] = p.mesh.size_range();
  fmt::print("vpcontact: {} — {}\n", c.name, c.description);
  fmt::print("  mesh: d = {}, {} nodes, {} cells, h in [{:.3g}, {:.3g}]; {} free displacement dofs, {} contact nodes\n",
             p.mesh.dim(), p.mesh.n_nodes(), p.mesh.n_cells(), hmin, hmax, stepper.dofs().n_free(),
             stepper.contact_nodes().size());
  fmt::print("  Γ1 (clamped): {}; Γ3 (contact): {}\n", fmt::join(p.clamped, ", "), fmt::join(p.contact.parts, ", "));
  fmt::print("  elasticity: {} (E = {}, nu = {}); G: {}; phi: {}\n", p.elasticity.name(), p.elasticity.young(),
             p.elasticity.poisson(), p.law->describe(), p.source->describe());
  fmt::print("  kappa = {}; T = {}, k = {}, N = {}; solvers: contact {}, damage {}; setup {:.3f} s\n", p.kappa,
             p.final_time, p.step(), p.n_steps, c.solvers.contact, c.solvers.damage, stepper.setup_seconds());
}

fs::path plot_script() {
  if (const char* env = std::getenv("VPCONTACT_PLOT_SCRIPT")) return env;
  return fs::path(VPC_SOURCE_DIR) / "scripts" / "vpcontact_plot.py";
}

int plot(const std::string& outdir) {
  const fs::path script = plot_script();
  vpc::require(fs::is_regular_file(script), "plot: the figure script '{}' is missing", script.string());
  vpc::require(fs::is_directory(outdir), "plot: '{}' is not a directory", outdir);
  const std::string cmd = fmt::format("/usr/bin/python3 '{}' '{}'", script.string(), outdir);
  const int rc = std::system(cmd.c_str());
  vpc::require(rc == 0, "plot: drawing the figures of '{}' failed (is python3-matplotlib installed?)", outdir);
  return 0;
}

int run(const Options& o, const CLI::App& cmd) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  if (vpc::use_petsc_engine(o.engine))  // mpirun -np P vpcontact run CASE (docs/parallel.md)
    return vpc::parallel_run([&](const vpc::MeshRequest& mesh) { return load_case(o, cmd, mesh); },
                             {o.quiet, o.resume, o.halvings, o.linear_solver, o.plot, o.checkpoint_every,
                              o.checkpoint_seconds});
  vpc::Case c = load_case(o, cmd);
  if (!o.resume.empty()) c.output.directory = o.resume;
  vpc::require(o.halvings >= 0 && o.halvings <= 20, "--retry-halvings must be in [0, 20] (got {})", o.halvings);
  c.solvers.max_halvings = o.halvings;
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
    vpc::remove_checkpoints(output.directory());  // a previous run's must not be resumed from
    output.start();
    checkpoint();
  }
  // Checkpoints: at step 0, at the end, and as the schedule says (by default by time).
  vpc::CheckpointSchedule schedule(o.checkpoint_every, o.checkpoint_seconds);
  vpc::Progress progress(c.problem->n_steps, o.quiet);
  while (!stepper.done()) {
    const vpc::StepReport r = stepper.step();
    if (!r.ok) {
      progress.finish();
      output.finish(std::chrono::duration<double>(Clock::now() - t0).count());
      const bool not_finite = std::isinf(r.contact.residuals.max()) || std::isinf(r.damage.kkt_residual);
      vpc::fail("step {} (t = {:.6g}) failed{}{}: contact solver {} after {} iterations (residual {:.2e}), damage solver {} "
                "after {} iterations (KKT residual {:.2e}, beta in [{}, {}]); tolerance {:.1e}. Results up to step {} "
                "are in '{}'; `--resume {}` continues from step {}{}",
                r.n, r.t, o.halvings > 0 ? fmt::format(" after {} step halvings", o.halvings) : "",
                not_finite ? " (NaN or Inf in the data of the step: a formula for phi, f0 or f2?)" : "",
                r.contact.converged ? "converged" : "did not converge", r.contact.iterations,
                r.contact.residuals.max(), r.damage.converged ? "converged" : "did not converge",
                r.damage.iterations, r.damage.kkt_residual, r.beta_min, r.beta_max, c.solvers.residual_tolerance,
                r.n - 1, output.directory().string(), output.directory().string(), last_checkpoint,
                o.halvings == 0 ? " (--retry-halvings N retries a failed step with smaller steps)" : "");
    }
    output.record(r);
    progress.update(r);
    if (stepper.done() || schedule.due(r.n)) {
      checkpoint();
      last_checkpoint = r.n;
      schedule.written();
    }
  }
  progress.finish();
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  output.finish(wall);
  if (!o.quiet)
    fmt::print("  done in {:.3f} s; results in {}/ (solution.pvd, history.csv, probes.csv, summary.json)\n", wall,
               output.directory().string());
  if (o.plot) return plot(output.directory().string());
  return 0;
}

int check(const Options& o, const CLI::App& cmd) {
  vpc::Case c = load_case(o, cmd);
  vpc::TimeStepper stepper(c.problem, c.solvers);  // validates, assembles, factorizes
  if (!o.quiet) describe(c, stepper);
  fmt::print("{}: ok\n", o.case_name);
  return 0;
}

void add_case_options(CLI::App* cmd, Options& o) {
  cmd->add_option("case", o.case_name, "a case file (.toml) or a built-in case: paper-1d, paper-2d, block-3d")
      ->capture_default_str();
  cmd->add_option("--set", o.sets, "override a case-file key, e.g. --set damage.kappa=0.1 (repeatable)");
  cmd->add_option("--kappa", o.kappa, "damage diffusion kappa (>= 0)");
  cmd->add_option("-n,--n", o.n, "mesh size: cells per edge (1D: segments; 2D: n x n squares; 3D: n^3 cubes)");
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

}  // namespace

int main(int argc, char** argv) {
  vpc::ensure_passive_omp_wait(argv);
  vpc::keep_freed_memory();
  CLI::App app{"vpcontact: quasistatic frictionless Signorini contact of elastic-viscoplastic bodies with damage\n"
               "(the fully discrete scheme of Fernandez & Sofonea, 2003)"};
  app.require_subcommand(0, 1);
  Options o;

  auto* run_cmd = app.add_subcommand("run", "run a case (default: paper-2d)");
  add_case_options(run_cmd, o);
  run_cmd->add_option("-o,--output", o.output, "output directory (default: the case's, else output/CASE)");
  run_cmd->add_option("--every", o.every, "write VTU every this many steps (0: final step only)");
  run_cmd->add_flag("--no-vtu", o.no_vtu, "write no VTU/PVD files (CSV and summary only)");
  run_cmd->add_flag("--plot", o.plot, "draw the figures (vpcontact plot) after the run");
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
  auto* plot_cmd = app.add_subcommand("plot", "draw the paper's figures from a run's output directory (PNG)");
  plot_cmd->add_option("outdir", o.outdir, "the output directory of a run")->required();
  auto* converge_cmd = vpc::add_converge_command(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*cases_cmd) {
      for (const auto& s : vpc::shipped_cases()) {
        fmt::print("{:10} {}\n", s.name, vpc::case_description(s.text));
      }
      fmt::print("(each is shipped as cases/<name>.toml, a starting point for your own cases)\n");
      return 0;
    }
    if (*plot_cmd) return plot(o.outdir);
    if (*converge_cmd) return vpc::run_converge_command();
    if (*check_cmd) return check(o, *check_cmd);
    return run(o, *run_cmd);  // `vpcontact` alone runs paper-2d
  } catch (const vpc::Error& e) {
    std::fflush(stdout);
    fmt::print(stderr, "vpcontact: error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "vpcontact: internal error: {}\n", e.what());
    return 2;
  }
}
