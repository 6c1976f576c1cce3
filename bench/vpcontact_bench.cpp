// vpcontact-bench: one timed run of a built-in case, printed as one JSON line.
//   vpcontact-bench CASE --n N [--steps S] [--vtu-every M] [--repeat-solves R]
//   mpirun -np P vpcontact-bench CASE --engine petsc [--linear-solver mumps|cg-gamg|cg-hypre] ...
// (the PETSc backend: a build with VPCONTACT_ENABLE_PETSC; rank 0 prints, sizes global).
// Reports the setup split (assembly, factorizations, contact setup), the median
// per-step time of each phase (sources G and φ, damage inequality, contact
// inequality, stress update, output), the median time of one forward+back solve
// with the cached factor of K, solver iterations, factor and model memory and the
// peak resident memory. bench/run_benchmarks.py repeats runs and tabulates medians.
#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "io/output_files.hpp"
#include "process_policy.hpp"
#include "io/run_output.hpp"
#include "scheme/time_stepper.hpp"
#ifdef VPCONTACT_WITH_PETSC
#include "la/petsc.hpp"
#include "parallel/petsc_engine.hpp"
#endif

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <numeric>
#include <random>

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double peak_rss_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return 1024.0 * static_cast<double>(u.ru_maxrss);
}

void set_damage_reduced(vpc::Case& c, const std::string& reduced) {
  vpc::require(reduced == "auto" || reduced == "capacitance" || reduced == "factor",
               "--damage-reduced: expected auto, capacitance or factor, got '{}'", reduced);
  c.solvers.damage_reduced = reduced == "capacitance" ? vpc::ReducedSolve::capacitance
                             : reduced == "factor"    ? vpc::ReducedSolve::reduced_factor
                                                      : vpc::ReducedSolve::automatic;
}

}  // namespace

int main(int argc, char** argv) {
  vpc::ensure_passive_omp_wait(argv);
  vpc::keep_freed_memory();
  CLI::App app{"vpcontact-bench: time one run of a built-in case (one JSON line on stdout)"};
  std::string name = "paper-2d", outdir = "/tmp/vpcontact-bench";
  int n = 40, steps = 100, vtu_every = -1, repeat_solves = 10;
  app.add_option("case", name, "built-in case")->capture_default_str();
  app.add_option("--n", n, "mesh size (cells per edge)")->capture_default_str();
  app.add_option("--steps", steps, "time steps")->capture_default_str();
  app.add_option("--vtu-every", vtu_every, "write VTU every this many steps (default: none)");
  app.add_option("--repeat-solves", repeat_solves, "solves timed for the one-solve cost")->capture_default_str();
  app.add_option("--output", outdir, "scratch output directory")->capture_default_str();
  std::vector<std::string> sets;
  app.add_option("--set", sets, "override a key of the case, e.g. --set damage.c=1 (repeatable)");
  std::string reduced = "auto";
  app.add_option("--damage-reduced", reduced, "damage active set: auto, capacitance or factor")->capture_default_str();
  std::string engine = "serial", linear_solver = "mumps";
  app.add_option("--engine", engine, "serial, or petsc (under mpirun; a PETSc build)")->capture_default_str();
  app.add_option("--linear-solver", linear_solver, "PETSc backend: mumps, cg-gamg or cg-hypre")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const bool petsc = engine == "petsc";
#ifdef VPCONTACT_WITH_PETSC
  if (petsc && PetscInitializeNoArguments() != 0) return 2;
  struct Finalize {
    bool on;
    ~Finalize() {
      if (on) PetscFinalize();
    }
  } finalize{petsc};
#endif

  try {
    const auto t_run = Clock::now();
    vpc::require(engine == "serial" || engine == "petsc", "--engine: expected serial or petsc, got '{}'", engine);
    const auto load = [&](const vpc::MeshRequest& m) {
      vpc::MeshRequest request = m;
      request.cells = n;
      return vpc::load_case(name, {.sets = sets, .steps = steps}, request);
    };
    std::unique_ptr<vpc::TimeStepper> made;
    vpc::Case c;
    if (petsc) {
#ifdef VPCONTACT_WITH_PETSC
      c = vpc::load_case_everywhere(load, vpc::la::make_mpi_comm(PETSC_COMM_WORLD));
      set_damage_reduced(c, reduced);
      vpc::PetscSolverOptions linear;
      linear.kind = linear_solver;
      made = vpc::petsc_stepper(PETSC_COMM_WORLD, c, linear);
#else
      vpc::fail("--engine petsc: this vpcontact-bench was built without PETSc (-DVPCONTACT_ENABLE_PETSC=ON)");
#endif
    } else {
      c = load({});
      set_damage_reduced(c, reduced);
      made = std::make_unique<vpc::TimeStepper>(c.problem, c.solvers);
    }
    vpc::TimeStepper& stepper = *made;
    const vpc::la::Comm& comm = stepper.comm();
    const bool root = comm.rank() == 0;
    vpc::OutputOptions out = c.output;
    out.directory = outdir;
    out.vtu = vtu_every > 0;
    out.every = std::max(vtu_every, 0);

    // The floor of a step: one solve with the cached factor of K (forward + back).
    std::vector<double> solve_times;
    stepper.stiffness_factor();  // made on demand under the primal contact solver: not part of a solve's time
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> U(-1, 1);
    vpc::Vector b(stepper.part().n_owned_dofs);
    for (int r = 0; r < repeat_solves; ++r) {
      for (auto& v : b) v = U(rng);
      const auto t0 = Clock::now();
      vpc::Vector x;
      stepper.stiffness_factor().solve(b, x);
      solve_times.push_back(seconds_since(t0));
      if (!std::isfinite(comm.sum(x.squaredNorm()))) return 3;
    }

    if (root) vpc::prepare_output_directory(out.directory);  // as the run loop does before set-up
    vpc::RunOutput output(stepper, out);
    output.start();
    std::vector<double> src, dmg, ct, st, total, outp;
    int max_ci = 0, max_di = 0, active = 0;
    double max_res = 0;
    bool ok = true;
    while (!stepper.done()) {
      const auto t0 = Clock::now();
      const vpc::StepReport r = stepper.step();
      const double t_step = seconds_since(t0);
      const auto t1 = Clock::now();
      output.record(r);
      const double t_out = seconds_since(t1);
      src.push_back(r.seconds_sources);
      dmg.push_back(r.seconds_damage);
      ct.push_back(r.seconds_contact);
      st.push_back(r.seconds_stress);
      outp.push_back(t_out);
      total.push_back(t_step + t_out);
      max_ci = std::max(max_ci, r.contact.iterations);
      max_di = std::max(max_di, r.damage.iterations);
      max_res = std::max({max_res, r.contact.residuals.max(), r.damage.kkt_residual});
      active = r.contact.n_active;
      ok = ok && r.ok;
    }
    const double wall = seconds_since(t_run);
    output.finish(wall);
    double sum_steps = 0;
    for (double t : total) sum_steps += t;
    const auto& s = stepper.setup_timing();
    const vpc::MeshPart& part = stepper.part();
    const double peak_rss = comm.max(peak_rss_bytes()), factor_bytes = comm.sum(stepper.factor_bytes()),
                 model_bytes = comm.sum(stepper.model_bytes());
    ok = comm.all(ok);
    const auto& cost = stepper.solver_cost();  // -1 in the JSON: no symbolic analysis (PETSc)
    if (root)
      fmt::print(
        "{{\"case\": \"{}\", \"n\": {}, \"steps\": {}, \"dofs\": {}, \"damage_dofs\": {}, \"contact_nodes\": {}, "
        "\"cells\": {}, \"setup\": {:.6f}, \"assembly\": {:.6f}, \"factor_K\": {:.6f}, \"factor_H\": {:.6f}, "
        "\"contact_setup\": {:.6f}, \"solve\": {:.6e}, \"step_median\": {:.6e}, \"sources\": {:.6e}, "
        "\"damage\": {:.6e}, \"contact\": {:.6e}, \"stress\": {:.6e}, \"output\": {:.6e}, \"steps_total\": {:.6f}, "
        "\"wall\": {:.6f}, \"max_contact_iterations\": {}, \"max_damage_iterations\": {}, \"active\": {}, "
        "\"max_residual\": {:.3e}, \"ok\": {}, \"factor_bytes\": {:.0f}, \"model_bytes\": {:.0f}, "
        "\"peak_rss_bytes\": {:.0f}, \"vtu_every\": {}, \"damage_s_total\": {:.6f}, \"factorizations\": {}, "
        "\"engine\": \"{}\", \"ranks\": {}, \"linear_solver\": \"{}\", \"estimate_direct\": {:.4g}, "
        "\"estimate_iterative\": {:.4g}, \"estimate\": \"{}\"}}\n",
        name, n, steps, part.n_global_dofs, part.n_global_nodes, part.n_contact, part.n_global_cells, s.total, s.assembly, s.factor_K, s.factor_H, s.contact, median(solve_times),
        median(total), median(src), median(dmg), median(ct), median(st), median(outp), sum_steps, wall, max_ci,
        max_di, active, max_res, ok ? "true" : "false", factor_bytes, model_bytes, peak_rss, vtu_every,
        std::accumulate(dmg.begin(), dmg.end(), 0.0), stepper.n_factorizations(), engine, comm.size(),
        stepper.backend().linear_solver(), cost ? cost->direct : -1.0, cost ? cost->iterative : -1.0,
        cost ? cost->detail : std::string());
    return ok ? 0 : 4;
  } catch (const std::exception& e) {
    fmt::print(stderr, "vpcontact-bench: error: {}\n", e.what());
    return 1;
  }
}
