#include "solvers/solver_cost.hpp"

#include <fmt/format.h>

namespace vpc {

SolverCost estimate_solver_cost(const FactorEstimate& K_factor, double K_nonzeros, double contact_nodes, int steps,
                                bool dual, const SolverRates& rates) {
  const double factor = K_factor.flops / rates.factor_flops_per_second;
  const double solve = K_factor.entries * rates.solve_seconds_per_entry;
  SolverCost c;
  if (dual) {
    // Forming S = N K⁻¹Nᵀ is m column solves (in blocks), then the steps' solves.
    const double schur = contact_nodes * rates.column_share * solve;
    const double run = steps * rates.dual_solves_per_step * solve;
    c.direct = factor + schur + run;
    c.detail = fmt::format("direct: factor of K {:.3g} s + S ({:.0f} columns) {:.3g} s + {} steps {:.3g} s", factor,
                           contact_nodes, schur, steps, run);
  } else {
    // The primal solver on a factor refactorizes K whenever the active set changes.
    const double refactor = steps * rates.primal_direct_factorizations_per_step * factor;
    const double run = steps * rates.dual_solves_per_step * solve;
    c.direct = factor + refactor + run;
    c.detail = fmt::format("direct: factor of K {:.3g} s + refactorizations at set changes {:.3g} s + {} steps {:.3g} s",
                           factor, refactor, steps, run);
  }
  c.iterative = steps * rates.cg_step_seconds_per_nonzero * K_nonzeros;
  c.detail += fmt::format("; CG + GAMG: {} steps {:.3g} s (factor: {:.3g} entries, {:.3g} flops)", steps,
                          c.iterative, K_factor.entries, K_factor.flops);
  return c;
}

}  // namespace vpc
