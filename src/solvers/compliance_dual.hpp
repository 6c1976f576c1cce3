#pragma once
// The dual of the contact problem (3.9) when some contact nodes follow a normal-
// compliance law that is not linear (SPEC §6): σ_ν = −c (u_ν − g)₊^e with e > 1, lumped
// at the node as λ_i = k_i (N_i u − g_i)₊^{e_i}, k_i = c |Γ3|_i. With the penetration
// d = N u − g = b − Sλ (S = N K⁻¹ Nᵀ, b = N K⁻¹F − g) it reads, row by row:
//   Signorini rows (k_i = ∞):  λ_i ≥ 0, d_i ≤ 0, λ_i d_i = 0  ⇔  min(λ_i, −d_i / S_ii) = 0,
//   compliance rows:           λ_i − k_i (d_i)₊^{e_i} = 0.
// It is the optimality system of min ½λᵀSλ − bᵀλ + Σ_i k_i^{−1/e} λ_i^{1+1/e} / (1 + 1/e)
// over λ ≥ 0: a strictly convex problem with one solution. For e = 1 everywhere it is
// the box QP with S + diag(1/k), which the active-set solver uses instead.
#include "solvers/box_qp.hpp"

namespace vpc {

/// Semismooth Newton on Φ(λ) = 0 (the rows above; the generalized Jacobian J takes the
/// λ branch of min at ties), with a backtracking line search on ½‖WΦ‖², W = diag(1/J_ii),
/// warm-started from `lambda`. `compliance`: 1/k_i per row, 0 for a Signorini row;
/// `exponent`: e_i ≥ 1 per row (unused where compliance is 0). Converged when
/// ‖Φ_i / J_ii‖∞ ≤ 1e-13 · max(‖λ‖∞, ‖b ⊘ diag S‖∞) (each row in units of λ's error);
/// kkt_residual is that norm relative to the same scale.
BoxQpResult solve_compliance_dual(const Eigen::MatrixXd& S, const Vector& b, const Vector& compliance,
                                  const Vector& exponent, Vector& lambda, int max_iterations = 100);

}  // namespace vpc
