#pragma once
// The penalty–duality algorithm of Bermúdez and Moreno (the paper's refs [2, 3]),
// the method the paper uses for both inequalities. For
//     min ½ xᵀHx − bᵀx   subject to  lo ≤ Ex ≤ hi,
// with ω > 0 and λ = 1/(2ω) it iterates
//     (H + ω EᵀE) x_k = b − Eᵀ q_k,
//     q_{k+1} = 2ω E x_k + q_k − 2ω P(2 E x_k + q_k / ω),
// P the projection onto the box; θ = q + ω E x is the Lagrange multiplier
// (θ_i ≥ 0 where the upper bound is active, ≤ 0 at the lower). The matrix
// H + ωEᵀE is constant, so it is factorized once. Convergence is linear.
//
// Written once over la/: x and b are this rank's owned entries, the rows of E (and
// lo, hi, q, θ) this rank's constraint rows; every scale and the KKT decision are
// reductions over H.comm(), so all ranks iterate alike.
#include "la/linear_solver.hpp"

#include <functional>
#include <string>

namespace vpc {

struct PenaltyDualityResult {
  bool converged = false;
  int iterations = 0;
};

class PenaltyDuality {
 public:
  /// Factorizes H + ω EᵀE once (H->plus, a factor by make_factor(name)); E: this
  /// rank's constraint rows × owned columns. Collective.
  PenaltyDuality(const la::SpdOperator& H, SparseMatrix E, double omega, const la::LinearSolverFactory& make_factor,
                 const std::string& name);
  /// One process: H in Eigen, CHOLMOD.
  PenaltyDuality(const SparseMatrix& H, SparseMatrix E, double omega);

  /// Iterates from the multiplier state q (warm start, kept between calls) until
  /// (x, θ) satisfies the KKT conditions to `tolerance`: bound violation relative
  /// to ‖x‖∞ and the bounds; for θ_i ≠ 0, min(|θ_i| / ‖θ, b‖∞, distance of Ex to
  /// the bound θ_i's sign calls for / ‖x‖∞). Hx + Eᵀθ = b holds at every iterate.
  /// `accept`, if given, may also declare an iterate converged (e.g. a problem-specific
  /// residual of its projection), checked every few iterations, on every rank
  /// (collective; the iterate is accepted when it accepts on every rank).
  PenaltyDualityResult solve(const Vector& b, const Vector& lo, const Vector& hi, Vector& x, Vector& theta,
                             double tolerance, int max_iterations,
                             const std::function<bool(const Vector&)>& accept = {});

  double omega() const { return omega_; }
  double factor_bytes() const { return factor_->factor_bytes(); }
  /// The multiplier state (the warm start of the next call), for checkpoints.
  const Vector& multiplier_state() const { return q_; }
  void set_multiplier_state(const Vector& q) { q_ = q; }

 private:
  SparseMatrix E_, Et_;
  double omega_;
  la::Comm comm_;
  std::unique_ptr<la::SpdOperator> Hp_;  // H + ωEᵀE (kept: iterative factors use it)
  std::unique_ptr<la::LinearSolver> factor_;
  Vector q_;  // multiplier state, kept between calls as a warm start
};

}  // namespace vpc
