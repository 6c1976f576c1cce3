#pragma once
// Friction in the primal active-set solver (issue 28, SPEC §7): the tangential half of
// Hüeber, Stadler & Wohlmuth's primal–dual active set ("A primal-dual active set algorithm for
// three-dimensional contact problems with Coulomb friction", SIAM J. Sci. Comput. 30, 2008).
//
// In w = Qu each tangent j of a contact row i is one dof (ContactConstraints::tangent_dof) and
// the slip increment is Δ_ij = w_j − h_ij. Each iteration keeps the system SPD, so that CG + AMG
// still solve it: a STICK row fixes its tangential dofs at w_j = h_ij (Δ = 0; λ_τ is the reaction
// there), a SLIP row gets a known force λ_τ,i = s_i d_i (the body gets −λ_τ: a right-hand side), a
// row out of contact is free (λ_τ = 0). After a solve, with q_i = λ_τ,i + c_i Δ_i (c_i = K_rot's
// diagonal at the row's tangent dofs, their mean) and HSW's bound s_i = tresca_i + μ_i max(0, λ_ν,i + c_ν,i (N_i u − g_i)):
// stick where s_i > 0 and |q_i| ≤ s_i, else slip with the force s_i q_i / |q_i| (the Euclidean
// norm: a disc in 3D). Only the stick set changes the matrix; new slip forces are a new
// right-hand side on the same factor. Coulomb's bound takes this iteration's λ_ν: the slip forces
// are iterated to their fixed point within the step (not lagged from the last step).
#include "solvers/contact_solver.hpp"

#include <vector>

namespace vpc {

class PrimalFriction {
 public:
  /// `diagonal`: K_rot's, for the c_i of the tangential update rule.
  PrimalFriction(const ContactConstraints& c, const Vector& diagonal);

  /// The first sets of a solve: rows in contact (`active`) slip with the warm start's λ_τ where it
  /// is at its bound (normal, tangential: this rank's rows of the last answer; empty: none), else
  /// stick where the row has a friction law (μ or tresca > 0); frictionless rows slip with no force.
  void start(const ContactConstraints& c, const std::vector<char>& active, const Vector& normal,
             const Vector& tangential);

  /// Fixes the tangent dofs of the stick rows.
  void fix(std::vector<char>& fixed) const;
  /// Stick rows: w_j = h_ij into `fixed_values`; slip rows: −λ_τ into `rhs`.
  void load(const ContactConstraints& c, Vector& rhs, Vector& fixed_values) const;
  /// λ_τ of this iterate (rows × (b − 1)): the reaction r = b − K_rot w at stick dofs, the force
  /// used at slip ones, 0 where a tangent has no dof.
  Vector forces(const Vector& r) const;

  struct Next {
    std::vector<char> stick;  // per row
    Vector force;             // the slip forces s_i d_i (0 at stick and free rows)
    double change = 0;        // max |new − used slip force| over rows that slip before and after
    std::vector<double> excess;  // per row: |q_i| − s_i for stick rows the rule would let slip, else −1
  };
  /// HSW's update from the iterate (w, λ_τ) with the bound s_i of each row (`bound`; 0 off contact).
  Next next(const ContactConstraints& c, const Vector& w, const Vector& tangential, const Vector& bound) const;
  /// Monotone (against cycling): of the stick rows that would slip, only the one with the largest
  /// excess over its bound (over every rank) does. Collective.
  void slip_one(Next& next, const la::Comm& comm) const;
  void take(Next&& next);
  /// Barzilai–Borwein's step for c (c_i γ): from the last two iterates, γ = Σ |δλ_τ|²/c_i /
  /// (−Σ δλ_τ·δΔ) over the rows that slip in both (1/the Rayleigh quotient of their compliance),
  /// at most 1, also across a change of the sets (only over the same sets, γ went stale while
  /// the monotone rule changed one row an iteration: shipped shear-3d failed at t = 0.7; now its
  /// 20 steps take 55 factorizations); kept where `update` is false (Anderson's map must hold still).
  /// Collective.
  void secant(const ContactConstraints& c, const Vector& w, const la::Comm& comm, bool update);
  /// The slip forces along their directions with new bounds (a zero force stays zero).
  void rescale(const Vector& bound);

  const std::vector<char>& stick() const { return stick_; }
  const Vector& force() const { return force_; }

 private:
  int t_ = 0;                  // tangents per row
  std::vector<int> dof_;       // per row × t_: the tangent dof, −1 where none
  std::vector<double> scale_;  // per row: c of the update rule
  std::vector<char> stick_;    // per row
  Vector force_;               // per row × t_: the slip forces used
  double gamma_ = 1;           // c_i γ in the update rule (secant)
  Vector last_force_, last_slip_;
  std::vector<char> last_stick_;
};

/// Anderson acceleration (type II; Walker & Ni, SIAM J. Numer. Anal. 49, 2011) of a fixed point
/// x = G(x) over vectors distributed like the contact rows: from the last `depth` iterates, the
/// combination of the G(x_k) whose residuals G(x_k) − x_k combine to the least norm. Coulomb's bound
/// s = tresca + μ λ_ν(s) over Tresca problems: a plain iteration contracts only by μ times the
/// coupling of tangential to normal forces, and not at all where that exceeds 1 (a sheared block
/// whose tangential forces tilt it: measured ratio ≈ −0.95 at μ = 1); a linear map's fixed point it
/// finds as GMRES would (in at most as many steps as unknowns). Collective.
class AndersonMixing {
 public:
  explicit AndersonMixing(int depth) : depth_(depth) {}
  Vector next(const la::Comm& comm, const Vector& x, const Vector& g);

 private:
  int depth_;
  std::vector<Vector> dx_, df_;  // differences of the iterates and of their residuals
  Vector x_last_, f_last_;
};

/// The rows' states packed for ActiveSetHistory: normal set and stick set together.
std::vector<char> contact_sets(const std::vector<char>& active, const std::vector<char>& stick);

}  // namespace vpc
