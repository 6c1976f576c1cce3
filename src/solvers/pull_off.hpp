#pragma once
// Whether a step of a body that only its bonds hold has an equilibrium (SPEC §9, issue 50). K is
// singular on the body's free rigid motions R (ContactConstraints::free_motions), so Ku = F − Nᵀλ has a
// solution only where Rᵀ(F − Nᵀλ) = 0: the rows' forces balance the load on those motions. Each row's
// force lies in its graph's range, λ_i ≥ lower_i (a bond pulls at most a_i L_i; a pressed row pushes
// without bound), so an equilibrium exists exactly where
//   B μ = Rᵀ F − B lower  has a solution μ ≥ 0,  B = Rᵀ Nᵀ (k × m, k ≤ 6 motions),
// a nonnegative least-squares problem (Lawson–Hanson) whose residual is what no force can balance:
// above round-off the load pulls the body off. This is the existence condition of the convex
// step problem itself (its energy is bounded below along R exactly then), so a pull-off is found
// before any solve, at the step where it happens, whatever the active-set iteration would visit.
#include "la/comm.hpp"
#include "solvers/contact_solver.hpp"

namespace vpc {

/// The share of the load on the free motions that no admissible contact forces balance:
/// ‖B μ* − t‖ / max(‖Rᵀ F‖, ‖B lower‖) at the nonnegative least-squares solution μ* (0: an equilibrium
/// exists; 0 as well where `c` has no free motions). Collective.
double unbalanced_share(const la::Comm& comm, const ContactConstraints& c, const Vector& F);

/// Lawson–Hanson's active-set method for min ‖B x − t‖₂ over x ≥ 0 (B: k × n, k small); returns x.
Eigen::VectorXd nonnegative_least_squares(const Eigen::MatrixXd& B, const Eigen::VectorXd& t);

/// The share above which a step is a pull-off: round-off of the sums, well below any load a bond holds.
constexpr double kPullOffShare = 1e-9;

}  // namespace vpc
