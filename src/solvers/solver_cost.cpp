#include "solvers/solver_cost.hpp"

#include <fmt/format.h>

namespace vpc {

SolverRates measured_rates() {
  SolverRates r;
  // foundation-3d, one process (docs/performance.md, "Direct or iterative"):
  r.factor_flops_per_second = 2.5e10;  // CHOLMOD's supernodal factorization, 2 BLAS threads (n = 30)
  r.solve_seconds_per_entry = 1.0e-9;  // one solve with the factor, per entry of L (n = 20, 30)
  r.column_share = 0.18;               // a column of S (solved in blocks of 8), per solve (n = 20-40)
  r.dual_solves_per_step = 2.4;        // the dual active set's solves a step
  r.primal_direct_factorizations_per_step = 0.5;  // the primal solver on a factor: at set changes
  r.cg_step_seconds_per_nonzero = 1.2e-7;  // a step of the primal solver on CG + GAMG (n = 40, 100 steps)
  // Issue 27: the contact start (the first steps' several solves, the hierarchy built) costs about
  // five steps more (n = 70: the first three steps 11.8 s each against 3.44 s on average), and
  // starting PETSc and GAMG on a small problem some 0.3 s (patch-3d: 1.2 s more than CHOLMOD here).
  r.cg_setup_seconds_per_nonzero = 5 * r.cg_step_seconds_per_nonzero;
  r.cg_fixed_seconds = 0.3;
  return r;
}

// A margin of 2: a rough estimate must not flip the choice where the paths are close. With the
// contact start counted (issue 27), the small Hertz case (13,672 unknowns, 2 steps:
// "direct 0.89 s, CG 0.136 s" chose CG, 25 % slower) stays direct, while hertz-3d as shipped
// (27,354 unknowns, 766 contact nodes: S costs 766 solves) takes CG, 1.3-1.7x faster here.
bool iterative_is_faster(const SolverCost& c) { return c.iterative < 0.5 * c.direct; }

SolverCost estimate_solver_cost(const FactorEstimate& K_factor, double K_nonzeros, double contact_nodes, int steps,
                                bool dual, const SolverRates& rates) {
  const double factor = K_factor.flops / rates.factor_flops_per_second;
  const double solve = K_factor.entries * rates.solve_seconds_per_entry;
  SolverCost c;
  if (dual) {
    // Forming S = N K⁻¹Nᵀ is m column solves (in blocks), then the steps' solves.
    const double schur = contact_nodes * rates.column_share * solve;
    const double run = steps * rates.dual_solves_per_step * solve;
    c.direct = rates.direct_fixed_seconds + factor + schur + run;
    c.detail = fmt::format("direct: factor of K {:.3g} s + S ({:.0f} columns) {:.3g} s + {} steps {:.3g} s", factor,
                           contact_nodes, schur, steps, run);
  } else {
    // The primal solver on a factor refactorizes K whenever the active set changes.
    const double refactor = steps * rates.primal_direct_factorizations_per_step * factor;
    const double run = steps * rates.dual_solves_per_step * solve;
    c.direct = rates.direct_fixed_seconds + factor + refactor + run;
    c.detail = fmt::format("direct: factor of K {:.3g} s + refactorizations at set changes {:.3g} s + {} steps {:.3g} s",
                           factor, refactor, steps, run);
  }
  const double setup = rates.cg_fixed_seconds + rates.cg_setup_seconds_per_nonzero * K_nonzeros;
  c.iterative = setup + steps * rates.cg_step_seconds_per_nonzero * K_nonzeros;
  c.detail += fmt::format("; CG + GAMG: set-up {:.3g} s + {} steps {:.3g} s (factor: {:.3g} entries, {:.3g} flops)", setup,
                          steps, c.iterative - setup, K_factor.entries, K_factor.flops);
  return c;
}

}  // namespace vpc
