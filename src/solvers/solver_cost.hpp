#pragma once
// Direct or iterative (issue 14): the wall time a run would take with the direct solver
// (CHOLMOD) and with CG + GAMG, estimated from the problem's sizes before anything costly
// is done: K's nonzeros, the factor's entries and flops from CHOLMOD's symbolic analysis,
// the number of contact nodes and of steps. The rates are measured on the project's
// machine (docs/performance.md, "Direct or iterative"); the choice only acts where the
// two differ by a wide margin, so a rough rate does not flip it.
#include "la/linear_solver.hpp"
#include "la/memory_estimate.hpp"

#include <string>

namespace vpc {

/// What a run costs by each path, in seconds, and why.
struct SolverCost {
  double direct = 0;     // factor K + the dual's S (m solves) + the steps' solves
  double iterative = 0;  // the steps of the primal solver on CG + GAMG
  std::string detail;    // both estimates by part, for the message
};

/// The rates the estimate scales; measured_rates() are this machine's (2 cores;
/// docs/performance.md, "Direct or iterative"), kept in solver_cost.cpp.
struct SolverRates {
  double factor_flops_per_second = 1;   // CHOLMOD's supernodal factorization
  double solve_seconds_per_entry = 0;   // one solve with the factor, per entry of L
  double column_share = 0;              // a column of S (solved in blocks of 8), per solve
  double dual_solves_per_step = 0;      // the dual active set's solves a step
  double primal_direct_factorizations_per_step = 0;  // the primal solver on a factor: at set changes
  double cg_step_seconds_per_nonzero = 0;   // a step of the primal solver on CG + GAMG
  double cg_setup_seconds_per_nonzero = 0;  // GAMG's hierarchy and the contact start's extra solves
  double cg_fixed_seconds = 0;              // starting PETSc (MPI) on one process
  double direct_fixed_seconds = 0;          // what the direct path costs whatever the size
};

/// This machine's rates.
SolverRates measured_rates();

/// The estimate for `steps` steps of a problem with K (`K_nonzeros`, both triangles; its
/// factor `K_factor` from the symbolic analysis) and m contact nodes. `dual`: the direct path
/// takes the dual solver (m ≤ kDualContactRows), else the primal one refactorizing at set changes.
SolverCost estimate_solver_cost(const FactorEstimate& K_factor, double K_nonzeros, double contact_nodes, int steps,
                                bool dual, const SolverRates& rates = measured_rates());

/// Whether auto takes the iterative path: estimated faster by the margin solver_cost.cpp sets.
bool iterative_is_faster(const SolverCost& c);

}  // namespace vpc
