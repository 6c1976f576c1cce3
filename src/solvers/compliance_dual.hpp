#pragma once
// The dual of the contact problem (3.9) when some contact nodes follow a compliance law
// that is not linear (ContactLaw::linear; SPEC §6): e.g. σ_ν = −c (u_ν − g)₊^e with e > 1,
// lumped at the node as λ_i = k_i (N_i u − g_i)₊^{e_i}, k_i = c |Γ3|_i. With the penetration
// d = N u − g = b − Sλ (S = N K⁻¹ Nᵀ, b = N K⁻¹F − g) it reads, row by row:
//   rigid (Signorini) rows:  λ_i ≥ 0, d_i ≤ 0, λ_i d_i = 0  ⇔  min(λ_i, −d_i / S_ii) = 0,
//   compliance rows:         λ_i − λ(d_i) = 0  (ContactLaw::force; k_i (d_i)₊^{e_i} for the power law).
// For a force law increasing in d it is the optimality system of a strictly convex problem
// over λ ≥ 0 (for the power law min ½λᵀSλ − bᵀλ + Σ_i k_i^{−1/e} λ_i^{1+1/e} / (1 + 1/e)),
// with one solution. For linear laws everywhere it is the box QP with S + diag(1/k), which
// the active-set solver uses instead.
#include "contact/contact_law.hpp"
#include "solvers/box_qp.hpp"

#include <vector>

namespace vpc {

/// Newton steps before solve_compliance_dual gives up (converged = false).
constexpr int kComplianceDualIterations = 100;

/// Semismooth Newton on Φ(λ) = 0 (the rows above; the generalized Jacobian J takes the
/// λ branch of min at ties), with a backtracking line search on ½‖WΦ‖², W = diag(1/J_ii),
/// warm-started from `lambda`. `laws`: each row's law; `compliance`: 1/k_i per row (unused on a
/// rigid row); `lower`: a rigid row's lower bound of λ_i (ContactLaw::dual_lower; empty: 0), its
/// row then min(λ_i − lower_i, −d_i / S_ii) = 0. Converged when
/// ‖Φ_i / J_ii‖∞ ≤ 1e-13 · max(‖λ‖∞, ‖b ⊘ diag S‖∞) (each row in units of λ's error);
/// kkt_residual is that norm relative to the same scale.
/// `bond`, `bond_length` (empty: none; ContactConstraints::bond): a bonded row's tension branch
/// (adhesion, SPEC §9) below λ = 0: on a rigid row the gap left is −d + λ_i/a_i where λ_i < 0 (and
/// `lower` holds −a_i L_i), on a compliant one λ(d) = a_i max(d, −L_i) where d ≤ 0. With it a linear
/// law's rows are solved here too (the graph is no longer one line through 0).
BoxQpResult solve_compliance_dual(const Eigen::MatrixXd& S, const Vector& b, const std::vector<const ContactLaw*>& laws,
                                  const Vector& compliance, Vector& lambda, int max_iterations = kComplianceDualIterations,
                                  const Vector& lower = Vector(), const Vector& bond = Vector(),
                                  const Vector& bond_length = Vector());

}  // namespace vpc
