#pragma once
// The dual of a frictionless contact step with adhesion's bonds (SPEC §9; ContactConstraints::bond) on
// Signorini and linear compliance rows. With the step's bonds a_j > 0 on rows B and S the dense
// N K⁻¹ Nᵀ with the compliance rows' springs 1/k_j on its diagonal (the caller's), it minimizes the
// strictly convex
//   ½λᵀSλ − bᵀλ + Σ_{j∈B} λ_j₋²/(2a_j)   over λ_j ≥ lower_j − a_j L_j,
// whose optimality is each row's graph: a closed or pressing row's own law where λ_j ≥ 0, the bond's
// λ_j = a_j max(d_j, −L_j) where λ_j < 0 (d = b − (S − diag(1/k))λ the penetration).
#include "solvers/box_qp.hpp"

#include <optional>

namespace vpc {

/// The primal–dual active set on λ with three states a row: off (at its lower bound: lower_j, or a
/// bonded row's pull −a_j L_j), on its law's branch (d_j = 0, or λ_j = k_j d_j), on its bond's spring
/// (λ_j = a_j d_j), chosen by the resolvent of the row's graph as the primal solver chooses them
/// (PrimalOperator::bonded_state); each iterate one dense solve of the rows that are on. Exact once the
/// states repeat (converged; `iterations` counts the solves); nothing where a set comes back, a reduced
/// system is not positive definite or 100 iterations pass (then solve_bond_split). `spring`: 1/k_j of
/// the compliance rows (0 on rigid ones); λ: warm start in, answer out.
std::optional<BoxQpResult> solve_bond_states(const Eigen::MatrixXd& S, const Vector& spring, const Vector& lower,
                                             const Vector& bond, const Vector& bond_length, const Vector& b,
                                             Vector& lambda);

/// The same problem as a box QP in more unknowns, which cannot cycle: λ = p − E q, p the pressing part
/// (lower ≤ p ≤ upper) and q ∈ [0, a L] the bonded rows' pull, with S₀ = S − diag(1/k) (the springs are
/// the pressing part's: Σ p²/(2k) + Σ q²/(2a) is the penalty), the quadratic
///   H = [S₀ + diag(1/k)   −S₀ E;  −Eᵀ S₀   EᵀS₀ E + diag(1/a)],  [b; −Eᵀ b],
/// positive definite ((p − Eq)ᵀS₀(p − Eq) + Σ p²/k + Σ q²/a vanishes only at 0), solved exactly and
/// finitely by solve_box_qp (also at the kink λ = 0 = d of untouched bonded rows, where p = q = 0 is
/// degenerate).
BoxQpResult solve_bond_split(const Eigen::MatrixXd& S, const Vector& spring, const Vector& lower, const Vector& upper,
                             const Vector& bond, const Vector& bond_length, const Vector& b, Vector& lambda);

}  // namespace vpc
