#pragma once
// The dual of one frictional contact step (SPEC §7) on the contact unknowns alone. With
// B = [N; T] (per node its normal row, then its d − 1 tangent rows, in λ's order: λ_ν, λ_τ),
// S = B K⁻¹ Bᵀ and b = B K⁻¹F − [g; h], the step's conditions are the optimality system of
//     min ½λᵀSλ − bᵀλ   over  λ_ν,i ∈ [lo_i, hi_i] (λ_ν,i ≥ 0 for Signorini),  |λ_τ,i| ≤ s_i,
// since r = b − Sλ is (N u − g, T u − h) = (the penetration, the slip increment Δ) at
// u = K⁻¹(F − Bᵀλ): r_ν ≤ 0 ⟂ λ_ν, and Δ_i lies in the normal cone of the disc at λ_τ,i
// (no slip below the bound, slip along λ_τ at it). s_i = min(tresca_i + μ_i λ_ν,i, limit_i):
// Tresca is a convex QP (in 2D a box QP), Coulomb (with or without its shear limit) a
// quasi-variational one, solved exactly as well. A linear compliance law's λ_ν = k d₊ adds 1/k to
// S's normal diagonal (the caller does); a law that is not linear (a power law λ_ν = k d₊^e) has
// the row λ_ν − λ(r_ν) = 0 in place of the projection (FrictionDualSets::force_law): the normal law
// is monotone, so the problem is Coulomb's with a monotone normal law, and the bound is its force.
#include "solvers/box_qp.hpp"
#include "solvers/contact_solver.hpp"

#include <vector>

namespace vpc {

/// Each node's sets, replicated (i < m; λ has m × block entries).
struct FrictionDualSets {
  int block = 2;          // d: λ_ν and d − 1 tangential forces per node
  Vector lo, hi;          // the normal force's bounds (ContactLaw::dual_lower at the row's datum, dual_upper)
  Vector tresca, mu;      // the bound s_i = min(tresca_i + μ_i max(λ_ν,i, 0), limit_i)
  Vector limit;           // Coulomb's shear limit as a force (+∞: none; empty: none anywhere)
  /// A normal law that is not linear (ContactLaw::linear; e.g. a power-law compliance): per node
  /// its law (nullptr where λ_ν is projected onto [lo, hi]: Signorini, a linear law with 1/k on
  /// S's diagonal) and its compliance 1/k_i. Empty: none. At such a node λ_ν = λ(d), d = r_ν the
  /// penetration, in place of the projection (S without 1/k there).
  std::vector<const ContactLaw*> force_law;
  Vector compliance;
  /// Adhesion (SPEC §9; ContactConstraints::bond), per node: the step's bond a_i and its length L_i;
  /// empty: none. A bonded Signorini node's λ_ν is the resolvent of its graph instead of the clamp:
  /// z_ν itself where z_ν > lo_i + a_i L_i (closed), a_i z_ν/(a_i + ρ_ν) on the bond's spring, lo_i (the
  /// pull −a_i L_i) below −(a_i + ρ_ν) L_i; its Coulomb bound is μ max(λ_ν, 0), 0 while it pulls.
  Vector bond, bond_length;
  /// Per node × (block − 1): the tangent exists (else its row of T is zero, a symmetry plane:
  /// λ_τ,ij = 0, and S has 1 on that diagonal so that the problem stays definite).
  std::vector<char> tangent;
  /// Per node its friction law (contact/friction_law.hpp: the set the projection P is onto); empty:
  /// the disc everywhere (Coulomb, Tresca).
  std::vector<const FrictionLaw*> friction;
  int nodes() const { return static_cast<int>(lo.size()); }
  const FrictionLaw& friction_of(int node) const {
    return friction.empty() ? disc_friction() : *friction[static_cast<std::size_t>(node)];
  }
  /// Node i's bound's data (FrictionBound::at gives s_i).
  FrictionBound bound_of(int node) const {
    return {tresca[node], mu[node], limit.size() > 0 ? limit[node] : std::numeric_limits<double>::infinity()};
  }
  bool discs() const;  // every node's set is the disc (no law overrides it)
  bool coulomb() const;  // some μ_i > 0 (then the bound moves with λ_ν)
};

/// The exact dual solution, warm-started from `lambda`:
/// - 2D Tresca (no μ): the box QP λ_ν ∈ [lo, hi], λ_τ ∈ [−s, s] (solve_box_qp; finite, with
///   its monotone guard against cycling);
/// - otherwise (Coulomb, or 3D where the set is a disc): semismooth Newton on Alart–Curnier's
///   Φ(λ) = λ − P(λ + ρ(b − Sλ)), P the projection of each node onto its set with the bound
///   s = tresca + μ P_ν (the normal force the same projection gives), ρ = 1/diag(S) (one ρ per
///   node for the tangents: the disc's normal cone is invariant only under a scalar). In 2D Φ
///   is piecewise linear and the Newton step is the primal–dual active set's (the slip rows
///   λ_τ = ±μ λ_ν are linear): exact once the sets repeat. A backtracking line search on ½‖Φ‖²
///   globalizes; where it finds no decrease, a node that sticks and would leave contact by the
///   step first slips in contact (its bound coupled) and the search is tried again; failing that
///   the full step is taken (counted in `cycles`, at most kFullSteps times), and converged = false
///   after max_iterations lets the step control retry a smaller step. Where μ > 1 and μ times
///   z_ν's round-off leaves the disc's radius unresolved, P takes the radius in that range nearest
///   λ_τ (and λ_ν = (radius − tresca)/μ, the slip law's). Converged when ‖Φ‖∞ ≤ 1e-13 max(‖λ‖∞, max_i |b_ν,i / S_νν,i|,
///   max tresca) (or, where no step decreases ½‖Φ‖², ≤ 1e-10: the round-off of an ill-conditioned
///   S); λ is then P(z), exactly in its set.
/// `iterations` counts Newton steps (reduced solves for the box QP).
BoxQpResult solve_friction_dual(DenseBoxQpOperator& S, const Vector& b, const FrictionDualSets& sets, Vector& lambda,
                                int max_iterations = 100);

/// Each node's sets, replicated (collective); `laws`: every row's normal law (empty: Signorini);
/// `lower`: every row's lower bound of λ_ν (ContactConstraints::lower_of; empty: 0);
/// `frictions`: every row's friction law (empty: the disc everywhere).
/// A missing tangent's row and column of S are zero (a zero row of T): 1 on its diagonal keeps
/// S definite, and its λ_τ is held at 0.
FrictionDualSets friction_sets(const la::Comm& comm, const ContactConstraints& c,
                               const std::vector<const ContactLaw*>& laws, const Vector& lower,
                               const std::vector<const FrictionLaw*>& frictions, Eigen::MatrixXd& S);

/// The box of 2D Tresca's QP (exposed for tests).
void tresca_box(const FrictionDualSets& sets, Vector& lo, Vector& hi);

/// The Alart–Curnier residual ‖λ − P(λ + ρ(b − Sλ))‖∞ relative to the scale above: 0 exactly
/// at the solution, for either path (tests, reports).
double friction_dual_residual(const Eigen::MatrixXd& S, const Vector& b, const FrictionDualSets& sets,
                              const Vector& lambda);

}  // namespace vpc
