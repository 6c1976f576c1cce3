#pragma once
// One step of the fully discrete scheme (SPEC §2, the paper's (3.5)–(3.9)): from the state at
// t_{n−1} to t_n with the step k, steps 1–5 in order, over the discrete system and its solvers.
// Like MFEM's ODESolver::Step: it advances the state and knows nothing of how k was chosen
// (scheme/step_control.hpp) or what is reported and checked (scheme/step_checks.hpp).
#include "scheme/friction_data.hpp"
#include "la/vector.hpp"
#include "scheme/discrete_system.hpp"
#include "scheme/scheme_solvers.hpp"
#include "scheme/state.hpp"
#include "scheme/step_data.hpp"
#include "scheme/step_report.hpp"

#include <memory>
#include <optional>
#include <vector>

namespace vpc {

/// Below this many cells the elementwise loops run on one thread.
constexpr int kParallelCells = 4096;

/// The lagged sources of step 1 per cell, at a state: G (3.6) and φ (3.8).
struct LaggedRates {
  std::vector<SymTensor> G;
  std::vector<double> phi;
};

/// G and φ per cell at the state s, β at the cell's centroid.
LaggedRates lagged_rates(const DiscreteSystem& sys, const State& s);

/// What a step leaves for its checks and its error estimate besides the new state.
struct StepTaken {
  StepReport report;  // n, t, k, the solvers' reports, max von Mises, the phases' times
  LaggedRates lagged;  // G_{n−1}, φ_{n−1}: the step's step 1
  Vector beta_before;  // β_{n−1}
  StepData data;       // F_n, u_D(t_n), g(t_n)
};

class SchemeStep {
 public:
  /// The work vectors on the part's layouts; friction's part of the step for `contact`.
  SchemeStep(const MeshPart& part, const ContactSpec& contact);
  /// Steps 1–5 from the state s at t_{n−1} to t_end = t_n with the step k (s.n is left to the
  /// caller: it counts accepted steps). u_free: the owned free dofs of u, the contact solver's
  /// warm start. Collective.
  StepTaken take(const DiscreteSystem& sys, SchemeSolvers& solvers, const SolverChoice& choice, State& s,
                 Vector& u_free, double k, double t_end);
  /// G_n, φ_n at the state s (computed at the end of a step for its error estimate, then
  /// step 1 of the next step).
  const LaggedRates& rates(const DiscreteSystem& sys, const State& s);
  /// The state was restored: its rates are computed again (the same values).
  void forget_rates() { rates_.reset(); }

 private:
  /// Step 1: G_{n−1}, φ_{n−1}, computed at the end of the step before (or now).
  LaggedRates take_rates(const DiscreteSystem& sys, const State& s);
  /// Step 2, (3.8): the box QP with H = M + kκA, r = M β_{n−1} + k F_φ.
  DamageReport solve_damage(const DiscreteSystem& sys, DamageSolvers& damage, const SolverChoice& choice, State& s,
                            const std::vector<double>& phi, double k);
  /// Step 4, (3.9): K u_n = F_n − Bᵀz_n − Nᵀλ with the contact conditions, u = u_D + ũ.
  ContactReport solve_contact(const DiscreteSystem& sys, ContactSolver& contact, State& s, Vector& u_free,
                              const StepData& data);

  la::Vector f_, phi_, u_, beta_;  // ghosted work vectors: the load, F_φ, u_free, β
  std::unique_ptr<const StepFriction> friction_;
  std::optional<LaggedRates> rates_;
};

/// Step 3, (3.6): z_n = z_{n−1} + k G_{n−1}.
void update_history(State& s, const std::vector<SymTensor>& G, double k);
/// Step 5, (3.6): ε_n = ε(u_n), σ_n = ℰε_n + z_n. Returns the largest von Mises stress over
/// every process. Collective.
double update_stress(const DiscreteSystem& sys, State& s);

}  // namespace vpc
