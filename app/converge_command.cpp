// vpcontact converge CASE: measures the convergence rate of the fully discrete
// scheme (Theorem 3.5 of Fernández & Sofonea) on a built-in case, a case file or a
// manufactured solution, writes CSV tables and a log–log plot.
#include "converge_command.hpp"

#include "child_process.hpp"
#include "figures.hpp"
#include "parallel_run.hpp"

#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "io/atomic_file.hpp"
#include "io/case_file.hpp"
#include "verification/convergence.hpp"
#include "verification/manufactured.hpp"
#include "verification/refine.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace vpc {

namespace {

namespace fs = std::filesystem;

struct ConvergeOptions {
  std::string case_name;
  std::string output;
  std::vector<std::string> sets;
  std::vector<std::string> sequence = {"hk"};
  std::string forcing = "continuous";
  int levels = 4;
  int reference_offset = 1;
  int n = -1, steps = -1, h_steps = -1, k_refinements = 1;
  double kappa = -1, tolerance = -1, adaptive = -1;
  std::string contact_solver, damage_solver;
  std::string engine = "auto", linear_solver = "mumps";
  bool solvers = false, no_plot = false, quiet = false;
  CLI::App* cmd = nullptr;
};

ConvergeOptions& options() {
  static ConvergeOptions o;
  return o;
}

bool given(const std::string& name) {
  const CLI::Option* opt = options().cmd->get_option_no_throw(name);
  return opt != nullptr && opt->count() > 0;
}

/// What a study needs: the base mesh, how to build a level, N0, an exact solution.
struct StudyInput {
  std::string name;
  std::string description;
  Mesh base_mesh;
  ProblemFactory factory;
  std::shared_ptr<const ExactSolution> exact;
  int base_steps = 0;
  SolverChoice solvers;
  std::optional<StepControl> step_control;  // the case's error control (its tolerance: level 0's)
};

StudyInput manufactured_input(const ConvergeOptions& o) {
  ManufacturedOptions m = manufactured_options_from_name(o.case_name);
  m.forcing = manufactured_forcing_from_name(o.forcing);
  if (o.n > 0) m.cells = o.n;
  if (o.steps > 0) m.n_steps = o.steps;
  if (given("--kappa")) {
    require(o.kappa >= 0, "--kappa must be >= 0 (got {})", o.kappa);
    m.kappa = o.kappa;
  }
  StudyInput in;
  in.name = o.case_name;
  in.base_mesh = manufactured_base_mesh(m);
  const ManufacturedCase base = make_manufactured_case(m, in.base_mesh, m.n_steps);
  in.description = fmt::format("manufactured solution on (0,1)^{}: law {}, source {}, kappa = {}, forcing {}", m.dim,
                               base.problem->law->describe(), base.problem->source->describe(), m.kappa, o.forcing);
  in.exact = base.exact;
  in.base_steps = m.n_steps;
  in.factory = [m](const Mesh& mesh, int n_steps) {
    return std::shared_ptr<const Problem>(make_manufactured_case(m, mesh, n_steps).problem);
  };
  return in;
}

StudyInput case_input(const ConvergeOptions& o) {
  CaseOverrides ov{.sets = o.sets};
  if (given("--kappa")) ov.kappa = o.kappa;
  if (given("--steps")) ov.steps = o.steps;
  MeshRequest mesh;
  if (given("--n")) mesh.cells = o.n;
  const auto builtins = builtin_case_names();
  if (!is_case_file(o.case_name) && std::find(builtins.begin(), builtins.end(), o.case_name) == builtins.end())
    fail("unknown case '{}'; built-in cases are: {}; manufactured: mms-LAW-Dd (LAW = elastic, maxwell, "
         "perzyna; D = 1, 2, 3); or give a case file, NAME.toml",
         o.case_name, fmt::join(builtins, ", "));
  const Case c = load_case(o.case_name, ov, mesh);
  StudyInput in;
  in.name = c.name;
  in.description = c.description;
  in.base_mesh = c.problem->mesh;
  in.base_steps = c.problem->n_steps;
  if (c.problem->step_control) {
    require(given("--steps"), "converge: {} has error-controlled steps; give the base grid's steps N0 with --steps "
                              "(the fixed-grid levels and the reference use N0 2^l steps)", o.case_name);
    in.step_control = c.problem->step_control;
    in.step_control->landings.clear();  // the study's levels land on the base grid's times
  }
  in.factory = same_data_on(c.problem);
  in.solvers = c.solvers;
  return in;
}

void plot(const fs::path& dir, bool quiet) {
  const fs::path script = script_path("VPCONTACT_CONVERGE_PLOT_SCRIPT", "vpcontact_converge_plot.py");
  require(fs::is_regular_file(script), "converge: the plot script '{}' is missing", script.string());
  std::vector<std::string> argv = {python_interpreter(), script.string(), dir.string()};
  if (quiet) argv.emplace_back("-q");
  const ChildResult r = run_child(argv);  // no shell: the directory's name is never interpreted
  require(r.ok(), "converge: drawing the plots in '{}' failed ({}; is python3-matplotlib installed?)", dir.string(),
          r.started ? fmt::format("exit code {}", r.exit_code) : r.error);
}

}  // namespace

CLI::App* add_converge_command(CLI::App& app) {
  ConvergeOptions& o = options();
  auto* cmd = app.add_subcommand(
      "converge", "measure the convergence rate of the scheme (Theorem 3.5): errors and observed rates, CSV and PNG");
  o.cmd = cmd;
  cmd->add_option("case", o.case_name,
                  "a built-in case (paper-1d, paper-2d, block-3d), a case file, or a manufactured solution "
                  "mms-LAW-Dd (LAW = elastic, maxwell, perzyna; D = 1, 2, 3)")
      ->required();
  cmd->add_option("--levels", o.levels, "number of measured levels (>= 2); a reference run is one level finer")
      ->capture_default_str();
  cmd->add_option("--sequence", o.sequence,
                  "hk: h and k halved together; h: h halved at fixed k; k: k halved at fixed h; all: the three; "
                  "none: no rate study (with --solvers); several separated by commas, e.g. hk,k")
      ->delimiter(',')
      ->check(CLI::IsMember({"hk", "h", "k", "all", "none"}))
      ->capture_default_str();
  cmd->add_option("-n,--n", o.n, "base mesh: cells per edge (the case's -n; manufactured: cells per unit edge)");
  cmd->add_option("--steps", o.steps, "base number of time steps N0 (level l of hk and k uses N0 2^l)");
  cmd->add_option("--h-steps", o.h_steps, "N of every level of the h sequence (default 4 N0)");
  cmd->add_option("--k-refinements", o.k_refinements,
                  "the k sequence runs on the base mesh refined this many times")
      ->capture_default_str();
  cmd->add_option("--reference-offset", o.reference_offset,
                  "the reference is this many levels finer than the last measured level (no exact solution)")
      ->capture_default_str();
  cmd->add_option("--forcing", o.forcing,
                  "manufactured sources: continuous (error O(h + k)) or discrete (the exact solution solves the "
                  "time-discrete scheme: spatial error alone)")
      ->check(CLI::IsMember({"continuous", "discrete"}))
      ->capture_default_str();
  cmd->add_option("--kappa", o.kappa, "damage diffusion kappa (>= 0)");
  cmd->add_option("--set", o.sets, "override a case-file key, e.g. --set damage.kappa=0.1 (repeatable)");
  cmd->add_flag("--solvers", o.solvers,
                "also compare the active-set and penalty-duality solvers on the h levels (agreement, iterations)");
  cmd->add_option("--contact-solver", o.contact_solver,
                  "auto (default: the dual active set for few contact nodes and a direct solver, else the primal), "
                  "active-set, primal-active-set or penalty-duality")
      ->check(CLI::IsMember(vpc::kContactSolverNames));
  cmd->add_option("--damage-solver", o.damage_solver, "active-set (default) or penalty-duality")
      ->check(CLI::IsMember({"active-set", "penalty-duality"}));
  cmd->add_option("--tolerance", o.tolerance, "largest relative KKT residual accepted at a step (default 1e-8)");
  cmd->add_option("--adaptive", o.adaptive,
                  "also run error-controlled levels with this tolerance, halved per level (sequences hk and k), and "
                  "compare every level at the base grid's times (a case with [time] tolerance has them already)");
  cmd->add_option("-o,--output", o.output, "output directory (default output/converge-CASE)");
  cmd->add_flag("--no-plot", o.no_plot, "write no PNG");
  cmd->add_flag("-q,--quiet", o.quiet, "print only the tables");
  cmd->add_option("--engine", o.engine, "auto (PETSc under mpirun, if built with it), serial or petsc")
      ->capture_default_str();
  cmd->add_option("--linear-solver", o.linear_solver, "PETSc engine: mumps (default), cg-gamg or cg-hypre");
  return cmd;
}

namespace {

/// The study on an engine: every process runs it (a distributed one makes each level's
/// stepper over its ranks); rank 0 prints and writes.
int converge_on(const EngineChoice& engine) {
  const ConvergeOptions& o = options();
  StudyInput in;
  // Every process reads the options and the case alike: a bad one is one error, reported once.
  la::collective(engine.comm, [&] {
    require(o.levels >= 2 && o.levels <= 8, "--levels must lie in 2..8 (got {})", o.levels);
    require(o.reference_offset >= 1, "--reference-offset must be >= 1 (got {})", o.reference_offset);
    require(!given("--n") || o.n >= 1, "--n must be >= 1 (got {})", o.n);
    require(!given("--steps") || o.steps >= 1, "--steps must be >= 1 (got {})", o.steps);
    require(o.k_refinements >= 0, "--k-refinements must be >= 0 (got {})", o.k_refinements);
    const bool mms = is_manufactured_case_name(o.case_name);
    require(mms || !given("--forcing"), "--forcing applies to manufactured cases (mms-...) only");
    in = mms ? manufactured_input(o) : case_input(o);
  });
  if (!o.contact_solver.empty()) in.solvers.contact = o.contact_solver;
  if (!o.damage_solver.empty()) in.solvers.damage = o.damage_solver;
  if (given("--tolerance")) {
    require(o.tolerance > 0, "--tolerance must be > 0 (got {})", o.tolerance);
    in.solvers.residual_tolerance = o.tolerance;
  }
  if (given("--adaptive")) {
    require(o.adaptive > 0, "--adaptive must be > 0 (got {})", o.adaptive);
    if (!in.step_control) in.step_control.emplace();
    in.step_control->tolerance = o.adaptive;
  }
  const fs::path dir = o.output.empty() ? fs::path("output") / ("converge-" + fs::path(in.name).stem().string())
                                        : fs::path(o.output);
  const bool root = engine.root;
  if (root) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    require(!ec && fs::is_directory(dir), "cannot create output directory '{}'", dir.string());
  }

  std::string log_text;
  auto say = [&](const std::string& s) {
    log_text += s;
    if (!o.quiet && root) {
      fmt::print("{}", s);
      std::fflush(stdout);
    }
  };
  auto table = [&](const std::string& s) {
    log_text += s;
    if (!root) return;
    fmt::print("{}", s);
    std::fflush(stdout);
  };
  say(fmt::format("vpcontact converge {}: {}\n  base mesh: d = {}, {} cells; N0 = {}; {} measured levels\n", in.name,
                  in.description, in.base_mesh.dim(), in.base_mesh.n_cells(), in.base_steps, o.levels));

  std::vector<RefinementSequence> sequences;
  for (const auto& name : o.sequence) {
    if (name == "none") continue;
    const std::vector<RefinementSequence> add =
        name == "all" ? std::vector{RefinementSequence::HK, RefinementSequence::H, RefinementSequence::K}
                      : std::vector{refinement_sequence_from_name(name)};
    for (auto s : add)
      if (std::find(sequences.begin(), sequences.end(), s) == sequences.end()) sequences.push_back(s);
  }
  require(!sequences.empty() || o.solvers, "--sequence none needs --solvers (nothing to do otherwise)");
  for (RefinementSequence seq : sequences) {
    ConvergenceOptions co;
    co.sequence = seq;
    co.levels = o.levels;
    co.reference_offset = o.reference_offset;
    co.solvers = in.solvers;
    co.base_steps = in.base_steps;
    co.log = [&](const std::string& s) { say(s + "\n"); };
    co.make_stepper = engine.make_stepper;
    co.step_control = in.step_control;
    Mesh base = in.base_mesh;
    if (seq == RefinementSequence::H) co.base_steps = o.h_steps > 0 ? o.h_steps : 4 * in.base_steps;
    if (seq == RefinementSequence::K) base = MeshHierarchy(in.base_mesh, o.k_refinements).mesh(o.k_refinements);
    say(fmt::format("sequence {}:\n", to_string(seq)));
    const ConvergenceResult r = run_convergence(in.name, base, in.factory, in.exact, co);
    if (!root) continue;  // the norms are on rank 0
    table(format_convergence_table(r));
    const fs::path csv = dir / fmt::format("convergence_{}.csv", to_string(seq));
    write_convergence_csv(r, csv.string());
    say(fmt::format("  wrote {}\n", csv.string()));
    if (!r.adaptive.empty()) {
      const fs::path adaptive_csv = dir / fmt::format("convergence_{}_adaptive.csv", to_string(seq));
      write_convergence_csv(r, adaptive_csv.string(), true);
      say(fmt::format("  wrote {}\n", adaptive_csv.string()));
    }
  }
  if (o.solvers) {
    say("solver agreement (h levels, N = N0):\n");
    const auto s = compare_solvers(in.base_mesh, in.factory, o.levels, in.base_steps, in.solvers,
                                   [&](const std::string& line) { say(line + "\n"); });
    table(format_solver_table(s));
    const fs::path csv = dir / "solvers.csv";
    write_solver_csv(s, csv.string());
    say(fmt::format("  wrote {}\n", csv.string()));
  }
  if (!root) return 0;
  write_file_atomic(dir / "converge.log", log_text);
  if (!o.no_plot) plot(dir, o.quiet);
  say(fmt::format("results in {}/\n", dir.string()));
  return 0;
}

}  // namespace

int run_converge_command() {
  const ConvergeOptions& o = options();
  if (!use_petsc_engine(o.engine)) return converge_on(serial_engine());
  require(!o.solvers, "--solvers compares the two solvers on the serial engine only (run it without mpirun)");
  RunOptions ro;
  ro.linear_solver = o.linear_solver;
  return parallel_run(ro, converge_on);
}

}  // namespace vpc
