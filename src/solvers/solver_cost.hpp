#pragma once
// Direct or iterative (issue 14): the wall time a run would take with the direct solver
// (CHOLMOD) and with CG + GAMG, estimated from the problem's sizes before anything costly
// is done: K's nonzeros, the factor's entries and flops from CHOLMOD's symbolic analysis,
// the number of contact nodes and of steps. The rates are measured on the project's
// machine (docs/performance.md, "Direct or iterative"); the choice only acts where the
// two differ by a wide margin, so a rough rate does not flip it.
#include "la/factor.hpp"
#include "la/memory_estimate.hpp"

#include <string>

namespace vpc {

/// What a run costs by each path, in seconds, and why.
struct SolverCost {
  double direct = 0;     // factor K + the dual's S (m solves) + the steps' solves
  double iterative = 0;  // the steps of the primal solver on CG + GAMG
  std::string detail;    // both estimates by part, for the message
};

/// The measured rates the estimate scales (this machine: 2 cores; docs/performance.md).
struct SolverRates {
  // foundation-3d, one process (docs/performance.md, "Direct or iterative"):
  double factor_flops_per_second = 2.5e10;  // CHOLMOD's supernodal factorization, 2 BLAS threads (n = 30)
  double solve_seconds_per_entry = 1.0e-9;  // one solve with the factor, per entry of L (n = 20, 30)
  double column_share = 0.18;               // a column of S (solved in blocks of 8), per solve (n = 20-40)
  double dual_solves_per_step = 2.4;        // the dual active set's solves a step
  double primal_direct_factorizations_per_step = 0.5;  // the primal solver on a factor: at set changes
  double cg_step_seconds_per_nonzero = 1.2e-7;  // a step of the primal solver on CG + GAMG (n = 40, 100 steps)
};

/// The estimate for `steps` steps of a problem with K (`K_nonzeros`, both triangles; its
/// factor `K_factor` from the symbolic analysis) and m contact nodes. `dual`: the direct path
/// takes the dual solver (m ≤ kDualContactRows), else the primal one refactorizing at set changes.
SolverCost estimate_solver_cost(const FactorEstimate& K_factor, double K_nonzeros, double contact_nodes, int steps,
                                bool dual, const SolverRates& rates = {});

/// Whether the iterative path is clearly faster: less than half the direct path's estimate.
inline bool iterative_is_faster(const SolverCost& c) { return c.iterative < 0.5 * c.direct; }

/// Thrown by the set-up of a run that may go on with CG + GAMG (SolverChoice::iterative_fallback)
/// when iterative_is_faster.
class IterativeIsFaster : public DirectSolverDeclined {
 public:
  using DirectSolverDeclined::DirectSolverDeclined;
};

}  // namespace vpc
