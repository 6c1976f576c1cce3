#pragma once
// Coulomb's bound in the primal solver's Newton step (HSW's full linearization; issue 28, split out
// of primal_active_set.cpp in issue 49): the nonsymmetric perturbation C of the operator
// (PrimalOperator) that couples a slip row's tangent dofs to its normal force, solved by GMRES with
// the operator's factor or multigrid hierarchy as preconditioner (la::LinearSolver::solve_perturbed).
#include "la/linear_solver.hpp"
#include "solvers/contact_solver.hpp"
#include "solvers/primal_friction.hpp"

#include <vector>

namespace vpc {

class PrimalOperator;

class CoulombCoupling {
 public:
  /// Coulomb's bound in Newton's step: at a slip row i in contact with μ_i > 0 and a direction n_i
  /// (`couple`: else none is coupled), the force on tangent dof j is tresca n_ij
  /// (PrimalFriction::load) plus μ_i n_ij λ_ν,i(w), λ_ν a reaction of w: on a Signorini row
  /// (b − K_rot w)_ν/α, on a compliant one (α w_ν − g)/k⁻¹. The w-part is the returned perturbation
  /// C of the matrix (nonsymmetric: row j takes −μ n_j/α times K_rot's row ν), the rest goes to
  /// `rhs`. A direct solver's spring change since its factor (PrimalOperator::spring_change) joins
  /// C, solved with it by GMRES. Empty: nothing to add on any rank (a plain solve). Sets coupled().
  ///
  /// A law_determines row's equation along n_i (−λ_τ(w)·v + tresca + μ λ_ν(w) = 0, v = the row's
  /// PrimalFriction::along: n on the disc) is solved over μ: the system is D (A + C) δ = D r with
  /// D = I − (1 − 1/μ) n vᵀ on its tangent dofs (weigh(); v·n = 1, vᵀ the spring = 0), its
  /// coupling entries and right-hand side (`law_rhs`) made over μ here (μ n_j/α → n_j/α: D C without
  /// forming μ K, 1e303 at μ = 1e300), and C' = (D − I) A + D (the spring change) + those entries.
  /// That equation carries μ times K w's round-off (μ = 1e8: a residual 5x the friction tolerance,
  /// however far GMRES goes), the scaled one λ_ν's own: the residual that is left is the normal
  /// equilibrium's at the force law_normal_force reports. The equations across n (3D: λ_τ's spring
  /// part) keep their scale. The perturbation reads `op` (its A and spring change) when applied.
  la::Perturbation build(const PrimalOperator& op, const PrimalFriction& friction, bool couple,
                         const std::vector<char>& active, const Vector& b, Vector& rhs, Vector& law_rhs);

  /// y ← D y (build()): at each law row's tangent dofs the part along n over μ (as (y − (y·v) n) +
  /// (y·v)/μ n: 1 − 1/μ is 1 in floating point at μ = 1e300, and D would be singular).
  void weigh(Vector& y) const;
  /// Whether some rank has law rows (D is not the identity): the right-hand side is weighed too.
  bool weighted() const { return weighted_; }
  /// Whether some rank's bound is in the matrix (the last build(); else C is only the kept factor's change).
  bool any_coupled() const { return any_entries_; }
  /// Per local row: its μ λ_ν in the matrix (the last build()).
  const std::vector<char>& coupled() const { return coupled_; }

  /// Whether row i's λ_ν is the one its slip law's row gives rather than its reaction (or its
  /// spring's force): at a row whose bound was coupled in the last solve (λ_τ = (tresca + μ λ_ν) n,
  /// one of its equations) with μ > 1. Both are the same λ_ν up to the solve's residual, but the
  /// reaction (b − K_rot w)_ν carries K w's round-off (the spring g − α w_ν's), which μ λ_ν multiplies
  /// into the bound (μ = 1e8: 2e-8 of the force scale, above the friction tolerance whatever the
  /// solve), while the law's row divides λ_τ's by μ.
  bool law_determines(Eigen::Index i, const ContactConstraints& c) const {
    return static_cast<std::size_t>(i) < coupled_.size() && coupled_[static_cast<std::size_t>(i)] && c.mu[i] > 1;
  }
  /// λ_ν = (λ_τ · v − tresca)/μ with λ_τ the reaction r at the row's tangent dofs (v: PrimalFriction::along).
  static double law_normal_force(Eigen::Index i, const Vector& r, const PrimalFriction& friction,
                                 const ContactConstraints& c);

 private:
  /// One entry of C, y[tangent] += coefficient × (K_rot x at the reaction row numbered `normal`
  /// among the coupled rows, if reaction; else x[normal]).
  struct Entry {
    int tangent, normal;
    double coefficient;
    bool reaction;
  };
  /// A law_determines row's tangent dofs (−1 where none), its direction n, its v and 1/μ (weigh()).
  struct LawRow {
    std::vector<int> dofs;
    Vector n, v;
    double inverse;
  };
  std::vector<Entry> entries_;
  std::vector<char> coupled_;  // per local row: its μ λ_ν in the matrix
  std::vector<LawRow> law_rows_;
  bool weighted_ = false;  // some rank has law rows
  bool any_entries_ = false;  // some rank has coupled rows
};

}  // namespace vpc
