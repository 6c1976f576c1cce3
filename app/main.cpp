// vpcontact: the command line on the library. `vpcontact run [CASE]` runs a case
// (default: the paper's 2D example) and writes VTU/PVD, CSV and a JSON summary.
#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "io/run_output.hpp"
#include "scheme/time_stepper.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <chrono>
#include <cstdio>

namespace {

struct RunOptions {
  std::string case_name = "paper-2d";
  std::string output;
  vpc::CaseOverrides overrides;
  double kappa = -1, dt = -1;
  int n = -1, steps = -1, every = -1;
  bool no_vtu = false, quiet = false;
  vpc::SolverChoice solvers;
};

int run(RunOptions& o, const CLI::App& cmd) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  if (cmd.count("--kappa")) o.overrides.kappa = o.kappa;
  if (cmd.count("--n")) o.overrides.mesh_cells = o.n;
  if (cmd.count("--steps")) o.overrides.steps = o.steps;
  if (cmd.count("--dt")) o.overrides.time_step = o.dt;
  vpc::BuiltinCase c = vpc::make_builtin_case(o.case_name, o.overrides);
  vpc::OutputOptions out;
  out.directory = o.output.empty() ? "output/" + c.name : o.output;
  out.every = cmd.count("--every") ? o.every : c.output_every;
  out.vtu = !o.no_vtu;
  out.probes = c.probes;

  vpc::TimeStepper stepper(c.problem, o.solvers);
  const auto& p = stepper.problem();
  if (!o.quiet) {
    fmt::print("vpcontact: {} — {}\n", c.name, c.description);
    fmt::print("  mesh: d = {}, {} nodes, {} cells; {} free displacement dofs, {} contact nodes\n", p.mesh.dim(),
               p.mesh.n_nodes(), p.mesh.n_cells(), stepper.dofs().n_free(), stepper.contact_nodes().size());
    fmt::print("  G: {}; phi: {}; kappa = {}; k = {}, N = {}\n", p.law->describe(), p.source->describe(), p.kappa,
               p.step(), p.n_steps);
    fmt::print("  solvers: contact {}, damage {}; setup {:.3f} s\n", o.solvers.contact, o.solvers.damage,
               stepper.setup_seconds());
    fmt::print("  {:>5} {:>7} {:>6} {:>13} {:>5} {:>9} {:>5} {:>9} {:>10} {:>10}\n", "step", "t", "active",
               "contact force", "it_c", "res_c", "it_d", "res_d", "beta_min", "beta_max");
  }
  vpc::RunOutput output(stepper, out);
  output.start();
  const int print_every = std::max(1, p.n_steps / 20);
  while (!stepper.done()) {
    const vpc::StepReport r = stepper.step();
    output.record(r);
    if (!o.quiet && (r.n % print_every == 0 || !r.ok || stepper.done()))
      fmt::print("  {:5d} {:7.4f} {:6d} {:13.6e} {:5d} {:9.2e} {:5d} {:9.2e} {:10.6f} {:10.6f}\n", r.n, r.t,
                 r.contact.n_active, r.contact.total_force, r.contact.iterations, r.contact.residuals.max(),
                 r.damage.iterations, r.damage.kkt_residual, r.beta_min, r.beta_max);
    if (!r.ok) {
      output.finish(std::chrono::duration<double>(Clock::now() - t0).count());
      vpc::fail("step {} (t = {}) failed: contact solver {} after {} iterations (residual {:.2e}), damage solver {} "
                "after {} iterations (KKT residual {:.2e}); tolerance {:.1e}. The last good state is in '{}'",
                r.n, r.t, r.contact.converged ? "converged" : "did not converge", r.contact.iterations,
                r.contact.residuals.max(), r.damage.converged ? "converged" : "did not converge",
                r.damage.iterations, r.damage.kkt_residual, o.solvers.residual_tolerance,
                output.directory().string());
    }
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  output.finish(wall);
  if (!o.quiet)
    fmt::print("  done in {:.3f} s; results in {}/ (solution.pvd, history.csv, probes.csv, summary.json)\n", wall,
               output.directory().string());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vpcontact: quasistatic frictionless Signorini contact of elastic-viscoplastic bodies with damage\n"
               "(the fully discrete scheme of Fernandez & Sofonea, 2003)"};
  app.require_subcommand(0, 1);

  RunOptions o;
  auto* run_cmd = app.add_subcommand("run", "run a case (default: paper-2d)");
  run_cmd->add_option("case", o.case_name, "built-in case: paper-1d, paper-2d, block-3d")->capture_default_str();
  run_cmd->add_option("-o,--output", o.output, "output directory (default: output/CASE)");
  run_cmd->add_option("--kappa", o.kappa, "damage diffusion kappa (>= 0)");
  run_cmd->add_option("-n,--n", o.n, "mesh size: cells per edge (1D: segments; 2D: n x n squares; 3D: n^3 cubes)");
  run_cmd->add_option("--steps", o.steps, "number of time steps N (k = T / N)");
  run_cmd->add_option("--dt", o.dt, "time step k (must divide T)");
  run_cmd->add_option("--every", o.every, "write VTU every this many steps (0: final step only)");
  run_cmd->add_flag("--no-vtu", o.no_vtu, "write no VTU/PVD files (CSV and summary only)");
  run_cmd->add_flag("-q,--quiet", o.quiet, "print nothing but errors");
  run_cmd->add_option("--contact-solver", o.solvers.contact, "active-set or penalty-duality")
      ->check(CLI::IsMember({"active-set", "penalty-duality"}))
      ->capture_default_str();
  run_cmd->add_option("--damage-solver", o.solvers.damage, "active-set or penalty-duality")
      ->check(CLI::IsMember({"active-set", "penalty-duality"}))
      ->capture_default_str();
  run_cmd->add_option("--tolerance", o.solvers.residual_tolerance,
                      "largest relative residual (contact KKT, damage KKT) accepted at a step")
      ->capture_default_str();

  auto* cases_cmd = app.add_subcommand("cases", "list the built-in cases");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*cases_cmd) {
      for (const auto& name : vpc::builtin_case_names())
        fmt::print("{:10} {}\n", name, vpc::make_builtin_case(name).description);
      return 0;
    }
    return run(o, *run_cmd);  // `vpcontact` and `vpcontact run` both run paper-2d
  } catch (const vpc::Error& e) {
    fmt::print(stderr, "vpcontact: error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "vpcontact: internal error: {}\n", e.what());
    return 2;
  }
}
