#pragma once
// Friction in the primal active-set solver (issue 28, SPEC §7): the tangential half of the
// semismooth Newton method of Hüeber, Stadler & Wohlmuth ("A primal-dual active set algorithm for
// three-dimensional contact problems with Coulomb friction", SIAM J. Sci. Comput. 30, 2008).
//
// In w = Qu each tangent j of a contact row i is one dof (ContactConstraints::tangent_dof) and the
// slip increment is Δ_ij = w_j − h_ij. With q_i = λ_τ,i + γ c_i Δ_i (c_i = K_rot's diagonal at the
// row's tangent dofs, their mean; γ ≤ 1 by secant()) and the bound s_i, the friction law is
// λ_τ,i = P_{s_i}(q_i), the projection onto the row's law's set C_{s_i}; for Coulomb and Tresca the
// disc |λ| ≤ s_i, where Newton's step linearizes P at the last iterate as:
//   STICK (|q_i| ≤ s_i): Δ_i = 0, the tangent dofs fixed at h_i (λ_τ their reaction);
//   SLIP (|q_i| > s_i, n_i = q_i/|q_i|): λ_τ,i = s_i n_i + k_i (I − n_i n_iᵀ) Δ_i with
//     k_i = s_i γ c_i / (|q_i| − s_i) (P's derivative (s/|q|)(I − nnᵀ) solved for the new λ_τ,i):
//     a constant force along n_i and a spring across it, symmetric positive semidefinite, so the
//     system stays SPD and CG + AMG still solve it. In 2D (one tangent) the spring vanishes.
// Any k_i ≥ 0 has the same fixed points (there k_i (I − nnᵀ)Δ_i = 0: Δ_i ∥ n_i); Newton's k_i
// makes the directions converge quadratically where the fixed point with k = 0 crawled (foundation-3d
// sliding: 49 solves a step, and none at n = 20 past step 71). Coulomb's bound s_i = tresca_i +
// μ_i λ_ν,i(w) enters Newton's step too (HSW's full linearization): at a slip row in contact
// the force s_i n_i is tresca_i n_i (load) plus μ_i n_i λ_ν,i(w), λ_ν a reaction of w, which the
// caller puts in the matrix (CoulombCoupling, primal_coupling.hpp) as a nonsymmetric coupling solved by GMRES
// with K's factor or preconditioner (la::LinearSolver::solve_perturbed). Coulomb holds exactly
// per step, not lagged from the last step, and no outer fixed point on s is needed. The iteration
// that drives these updates: primal_friction_iteration.hpp; Newton's spring is capped at
// primal_tuning::kMostSpring c (primal_tuning.hpp).
//
// Any law's set C_s = s C_1 (contact/friction_law.hpp) linearizes the same way with its projection
// P(q, s) and P's derivatives D = ∂P/∂q, p_s = ∂P/∂s at the iterate's q: Newton's λ_τ = P + D δq + p_s δs
// with P = D q + p_s s (Euler's identity: P is homogeneous of degree 1 in (q, s)) is
// (I − D) λ_τ = p_s s + γ c D Δ, i.e. λ_τ = s n + K Δ with n = (I − D)⁻¹ p_s (the point P/s of ∂C_1)
// and K = γ c (I − D)⁻¹ D. D is symmetric (a projection's derivative) with the set's outward normal
// ν̂ ∥ q − P in its kernel, so with two tangents D = d ττᵀ (τ ⊥ ν̂) and K = k (I − ν̂ν̂ᵀ),
// k = γ c d/(1 − d): a force along n and a spring across ν̂ again. On the disc n = ν̂ = q/|q|,
// d = s/|q| and k = s γ c/(|q| − s): the formulas above, which the disc keeps computing as they are.
#include "solvers/contact_solver.hpp"

#include <vector>

namespace vpc {

class PrimalFriction {
 public:
  /// `diagonal`: K_rot's, for the c_i of the update rule.
  PrimalFriction(const ContactConstraints& c, const Vector& diagonal);

  /// The first sets of a solve: rows in contact (`active`) slip with the warm start's λ_τ where it
  /// is at its bound (normal, tangential: this rank's rows of the last answer; empty: none), else
  /// stick where the row has a friction law (μ or tresca > 0); frictionless rows slip with no force.
  void start(const ContactConstraints& c, const std::vector<char>& active, const Vector& normal,
             const Vector& tangential);

  /// Fixes the tangent dofs of the stick rows.
  void fix(std::vector<char>& fixed) const;
  /// The slip rows' springs k_i (I − ν̂_i ν̂_iᵀ) of this linearization on their tangent dofs (owned
  /// numbering), appended to `out`.
  void springs(std::vector<Eigen::Triplet<double>>& out) const;
  /// Zeros on every row's tangent block (where a spring can be), appended to `out`.
  void spring_pattern(std::vector<Eigen::Triplet<double>>& out) const;
  /// Stick rows: w_j = h_ij into `fixed_values`; slip rows: −s_i n_i + k_i (I − ν̂_i ν̂_iᵀ) h_i into
  /// `rhs`, with s_i = tresca_i at the `coupled` rows (their μ λ_ν part is the caller's).
  void load(const ContactConstraints& c, const std::vector<char>& coupled, Vector& rhs, Vector& fixed_values) const;
  /// n_i of a slip row (on the boundary of its law's C_1: a unit vector on the disc; zero where it has no
  /// direction yet, and at stick rows).
  Eigen::Ref<const Vector> direction(std::size_t i) const {
    return direction_.segment(static_cast<Eigen::Index>(i) * t_, t_);
  }
  /// v_i of a slip row: v·n_i = 1 and v ⊥ its spring's range, so that v·λ_τ,i = s_i whatever the slip
  /// (ν̂/(ν̂·n) with ν̂ its set's normal; n_i on the disc). Zero where n_i is.
  Vector along(std::size_t i) const;
  /// s_i n_i of a slip row (the bound of its linearization along n_i; zero at stick rows).
  Eigen::Ref<const Vector> slip_force(std::size_t i) const {
    return force_.segment(static_cast<Eigen::Index>(i) * t_, t_);
  }
  int tangents() const { return t_; }
  int tangent_dof(std::size_t i, int j) const { return dof_[i * t_ + j]; }
  /// λ_τ of the iterate (rows × (b − 1)): the reaction r = b − K_rot w at the tangent dofs, 0
  /// where a tangent has no dof.
  Vector forces(const Vector& r) const;

  struct Next {
    std::vector<char> stick;  // per row
    std::vector<char> bond;   // per row: a tangential bond's state (kBondSpring, kBondPulled; 0: none)
    Vector force;             // s_i n_i per slip row (0 at stick and free rows)
    Vector direction;         // n_i per slip row (0 where q_i = 0 and at stick rows)
    Vector normal;            // ν̂_i per slip row of a law that is not the disc (its spring's axis)
    std::vector<double> spring;
    double change = 0;           // max over rows that slip before and after of |new s n − this iterate's λ_τ|
    std::vector<double> excess;  // per row: |q_i|_C − s_i for stick rows the rule would let slip, else −1
  };
  /// Newton's next linearization from the iterate (w, λ_τ) with the bound s_i of each row (`bound`; 0 off contact).
  Next next(const ContactConstraints& c, const Vector& w, const Vector& tangential, const Vector& bound) const;
  /// HSW's rule releases a stick row whose normal force λ_ν + c (N u − g) turned negative twice in one
  /// update: out of contact (`in_contact`'s row 0) and, its bound then 0, free. But that λ_ν is the
  /// stick state's, whose own reaction λ_τ can pull the node off: free, it slides and presses in
  /// again, sticks, and the two states alternate (a face's trailing node leaving contact under a large
  /// μ, where the slip state between them, in contact with μ λ_ν = |λ_τ|, is the answer). So
  /// the tangent is released first: such a row (μ > 0, its bound at λ_ν = 0 below its stick reaction)
  /// stays in contact and slips along λ_τ, Coulomb's bound coupled (its λ_ν that of the slip state),
  /// and leaves contact once its force is negative while it slips. `was_active`: the normal set
  /// of the iterate; `bound`: the next bounds (at λ_ν = 0 for rows out of `in_contact`).
  void slip_before_leaving(const ContactConstraints& c, const std::vector<char>& was_active, const Vector& tangential,
                           const Vector& bound, std::vector<char>& in_contact, Next& next) const;
  /// Monotone (against cycling): of the stick rows that would slip, only the one with the largest
  /// excess over its bound (over every rank) does. Collective.
  void slip_one(Next& next, const la::Comm& comm) const;
  /// The next linearization. (Its springs change the matrix. They cannot simply be kept from an
  /// earlier iterate: k (I − aaᵀ) with a ≠ n_i moves the fixed point off the law's solution, and the
  /// 3D test block then never converged; a direct solver keeps its factor and puts their change in
  /// GMRES's operator, PrimalOperator::change.)
  void take(Next&& next);
  /// Barzilai–Borwein's step for c (c_i γ): from the last two iterates (w, λ_τ `tangential`), γ = Σ |δλ_τ|²/c_i /
  /// (−Σ δλ_τ·δΔ) over the rows that slip in both (1/the Rayleigh quotient of their compliance),
  /// at most 1, also across a change of the sets; kept where `update` is false. Any c > 0 has the
  /// same solution; Newton's iteration converges from farther with this one (the 3D test block
  /// sheared non-uniformly: with c = K's diagonal the slip forces swung by half their size for
  /// ever). Collective.
  void secant(const ContactConstraints& c, const Vector& w, const Vector& tangential, const la::Comm& comm, bool update);

  /// The slip forces along their directions with new bounds (a zero force stays zero).
  void rescale(const Vector& bound);

  const std::vector<char>& stick() const { return stick_; }
  /// Per row, a tangential bond's state (SPEC §9's γ_τ on a frictionless row; ContactConstraints::shear_bond):
  /// 0 none; kBondSpring within the bond length, λ_τ = a_τ v (the spring a_τ on the tangent dofs);
  /// kBondPulled beyond it, λ_τ = a_τ L n (n = v/|v|, Newton's spring a_τ L/|v| across n, as a slip row's).
  /// v = Δ + v_{n−1} = w_t − (h − v_{n−1}): the bond's stretch. Never stick.
  static constexpr char kBondSpring = 1, kBondPulled = 2;
  const std::vector<char>& bond() const { return bond_; }

 private:
  /// Row i slipping at the trial force z (q_i, or λ_τ,i) outside C_s (or s = 0): its force s n, n, the
  /// set's normal ν̂ and Newton's spring k (uncapped), from its law's projection (the header's comment).
  struct Slip {
    Vector force, direction, normal;
    double spring = 0;
  };
  Slip slip(const FrictionLaw& law, std::size_t i, const Vector& z, double s) const;
  /// Row i's spring k_i (I − ν̂_i ν̂_iᵀ) over its tangents (zero rows and columns where a tangent has no
  /// dof); ν̂ = n on the disc.
  Eigen::MatrixXd across(std::size_t i) const;

  int t_ = 0;                   // tangents per row
  std::vector<int> dof_;        // per row × t_: the tangent dof, −1 where none
  std::vector<double> scale_;   // per row: c of the update rule
  std::vector<char> stick_;     // per row
  Vector force_;                // per row × t_: s n of the slip rows
  Vector direction_;            // per row × t_: n of the slip rows
  Vector normal_;               // per row × t_: ν̂ of the slip rows whose law's set is not the disc
  std::vector<char> disc_;      // per row: its law's set is the disc
  std::vector<double> spring_;  // per row: k of the slip rows (0 in 2D, at stick and free rows); a_τ on kBondSpring
  std::vector<char> bond_;      // per row: its tangential bond's state (bond())
  /// A tangential bond's state at its stretch v (a_τ: its stiffness, L its length), with its force, direction
  /// (zero within L) and spring (a_τ within L, Newton's a_τ L/|v| beyond).
  struct BondState {
    char state = 0;
    Vector force, direction;
    double spring = 0;
  };
  BondState bond_state(const Vector& v, double a, double L) const;
  /// h − v_{n−1} of a bonded row (its spring's rest position in w), h elsewhere.
  Vector rest(const ContactConstraints& c, std::size_t i) const;
  double gamma_ = 1;            // c_i γ in the update rule (secant)
  Vector last_force_, last_slip_;
  bool have_last_ = false;
  std::vector<char> last_stick_;
};

/// |l|_C, the size of a tangential force in its law's gauge (on the disc Eigen's norm, as the primal
/// solver computed it before the laws).
double force_size(const FrictionLaw& law, Eigen::Ref<const Vector> l);

/// The rows' states packed for ActiveSetHistory: normal set, stick set and tangential bonds' states together.
std::vector<char> contact_sets(const std::vector<char>& active, const std::vector<char>& stick,
                               const std::vector<char>& bond);

}  // namespace vpc
