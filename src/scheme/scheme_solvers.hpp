#pragma once
// The solvers a step uses, set up once over the discrete system (scheme/discrete_system.hpp):
// the factor of K, the contact solver of (3.9) (S = N K⁻¹ Nᵀ, or the primal one over K with
// its active rows) and the damage solvers of (3.8), one per step size in use.
#include "scheme/discrete_system.hpp"
#include "scheme/solver_choice.hpp"
#include "solvers/contact_solver.hpp"
#include "solvers/damage_solver.hpp"
#include "solvers/solver_cost.hpp"

#include <memory>
#include <optional>
#include <vector>

namespace vpc {

/// The damage solvers of H = M + kκA: kept for the step sizes in use (at most four; the least
/// recently used is dropped beyond that), so that a run with a few step sizes factors H once
/// per size. Switching hands on the warm start (it is the state's).
class DamageSolvers {
 public:
  /// The solver for step k. `H`: that matrix already assembled (set-up's), else it is
  /// assembled here when needed.
  DamageSolver& for_step(const DiscreteSystem& sys, const SolverChoice& choice, double k,
                         std::unique_ptr<la::SpdOperator> H = nullptr);
  /// The last one used: it holds the warm start.
  DamageSolver& current() const { return *current_; }
  int n_factorizations() const;
  double factor_bytes() const;
  /// The matrices H made so far.
  int n_matrices() const { return matrices_made_; }

 private:
  struct ForStep {
    double k = 0;
    std::unique_ptr<DamageSolver> solver;
  };
  std::vector<ForStep> kept_;  // most recently used last
  DamageSolver* current_ = nullptr;
  int dropped_factorizations_ = 0;  // of damage solvers no longer kept
  int matrices_made_ = 0;
};

struct SchemeSolvers {
  ContactSolverPick contact_pick;
  /// Of K; made on demand under the primal contact solver (which factors K with its active rows).
  std::shared_ptr<la::LinearSolver> K_factor;
  std::unique_ptr<ContactSolver> contact;
  DamageSolvers damage;
};

class PairSlider;

/// Factorizes K (after check_before_factorizing) and H of the first step, and sets up the
/// contact solver, telling each stage to choice.on_setup_stage and timing it in `timing`;
/// hands sys.K_local to the slider (PairSlider::keep_stiffness: kept where a pair slides large,
/// else released) and releases sys.H_first. `cost`: check_before_factorizing's estimate. Collective.
SchemeSolvers set_up_solvers(DiscreteSystem& sys, const SolverChoice& choice, PairSlider& slider,
                             SetupTiming& timing, std::optional<SolverCost>& cost);

/// The contact solver again, of the same kind, for the rows sys.contact has now (large-sliding
/// pairs, scheme/pair_slider.hpp), its warm state carried over; the primal's K_rot from K_local
/// (the part's K, which the slider keeps).
void remake_contact_solver(const DiscreteSystem& sys, const SolverChoice& choice, SchemeSolvers& s,
                           const SparseMatrix& K_local);

}  // namespace vpc
