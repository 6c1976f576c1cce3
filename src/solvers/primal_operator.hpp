#pragma once
// The operator the primal contact solver keeps (issue 14; split out of primal_active_set.cpp in
// issue 49): K_rot = Pᵀ K P (contact_basis, primal_active_set.hpp) with the active Signorini rows
// fixed, springs on the active compliant rows and what the rows' tangents add (TangentialPart: with
// friction the stick rows' tangent dofs fixed and the slip rows' springs); its factorization, kept
// while the sets hold; and one iterate of the active-set Newton method on it: the constrained solve
// (with Coulomb's coupling, CoulombCoupling, by GMRES) and the normal set's update.
#include "la/linear_solver.hpp"
#include "solvers/contact_frame.hpp"
#include "solvers/contact_solver.hpp"

#include <memory>
#include <optional>
#include <vector>

namespace vpc {

class PrimalOperator;

/// What the contact rows' tangents add to the operator's solves, the iteration's part (so that the
/// operator never asks whether there is friction): the stick rows' fixed dofs, the slip rows' springs
/// and loads, Coulomb's coupling. Without friction the rows have no tangents and it adds nothing
/// (NoTangents); with it FrictionalSolve (primal_friction_iteration.hpp).
class TangentialPart {
 public:
  virtual ~TangentialPart() = default;
  /// The fixed tangent dofs and the springs of this linearization, into the operator's.
  virtual void constrain(std::vector<char>& fixed, std::vector<Eigen::Triplet<double>>& springs) const = 0;
  /// Zeros wherever a spring can be, so that the factored matrix keeps its pattern as they change.
  virtual void spring_pattern(std::vector<Eigen::Triplet<double>>& springs) const = 0;
  /// Whether a direct solver keeps its factor while it serves as GMRES's preconditioner (keep_factor):
  /// where the operator changes from iterate to iterate (the slip rows' springs), not only with the sets.
  virtual bool keeps_factor() const = 0;
  /// Adds the tangential rows' load to `rhs` and their fixed values to `fixed_values` for the normal
  /// set `active` (b: the rotated load); returns the perturbation C of the matrix (Coulomb's coupling;
  /// empty: none).
  virtual la::Perturbation load(const PrimalOperator& op, const std::vector<char>& active, const Vector& b,
                                Vector& rhs, Vector& fixed_values) = 0;
  /// The right-hand side once the fixed rows are set: weighed where C is (CoulombCoupling::weigh).
  virtual void weigh(Vector& rhs) const = 0;
  /// Where the iterate is solved for its correction (the residual as the right-hand side) rather than
  /// for w itself (`perturbed`: C is not empty; `tight`, `iterative`: the solve's and the solver's):
  /// the target of its residual, and whether an iterative solver's forcing follows that target.
  struct Correction {
    double target = 0;
    bool follow = false;
  };
  virtual std::optional<Correction> correction(bool perturbed, bool tight, bool iterative) const = 0;
  /// Whether row i's λ_ν is its slip law's (CoulombCoupling::law_determines), and that force.
  virtual bool law_determines(Eigen::Index i, const ContactConstraints& c) const = 0;
  virtual double law_normal_force(Eigen::Index i, const Vector& r, const ContactConstraints& c) const = 0;
};

/// Rows without tangents (frictionless contact): nothing to add.
class NoTangents final : public TangentialPart {
 public:
  void constrain(std::vector<char>&, std::vector<Eigen::Triplet<double>>&) const override {}
  void spring_pattern(std::vector<Eigen::Triplet<double>>&) const override {}
  bool keeps_factor() const override { return false; }
  la::Perturbation load(const PrimalOperator&, const std::vector<char>&, const Vector&, Vector&, Vector&) override {
    return {};
  }
  void weigh(Vector&) const override {}
  std::optional<Correction> correction(bool, bool, bool) const override { return std::nullopt; }
  bool law_determines(Eigen::Index, const ContactConstraints&) const override { return false; }
  double law_normal_force(Eigen::Index, const Vector&, const ContactConstraints&) const override { return 0; }
};

class PrimalOperator {
 public:
  /// The arguments of make_primal_active_set_solver; refuses a row whose law is neither Signorini
  /// nor linear compliance.
  PrimalOperator(std::shared_ptr<const la::SpdOperator> K, std::shared_ptr<const la::SpdOperator> K_rot,
                 std::shared_ptr<la::LinearSolver> factor, ContactConstraints c);

  const ContactConstraints& constraints() const { return c_; }
  void set_gap(const Vector& gap) { c_.gap = checked_gap(c_, gap); }
  /// Adhesion's bonds of the step (ContactConstraints::bond): each bonded row's lower bound −a_i L_i.
  void set_bond(const StepBonds& bonds);
  void set_friction(const Vector& tresca, const Vector& shift) { set_friction_data(c_, tresca, shift); }
  const la::SpdOperator& K() const { return *K_; }
  const la::SpdOperator& K_rot() const { return *K_rot_; }
  const la::Comm& comm() const { return K_->comm(); }
  const la::LinearSolver* factor() const { return factor_.get(); }
  bool iterative() const { return factor_->iterative(); }
  /// K_rot's diagonal.
  const Vector& diagonal() const { return diagonal_; }
  /// K_rot (+ springs) with the factored set's rows fixed: what the factor holds.
  const la::SpdOperator& A() const { return *A_; }
  /// Whether the operator now (the sets and springs of the last iterate) differs from A (a direct
  /// solver with friction keeps its factor while it serves); y = (A now − A) x (collective).
  bool changed() const { return changed_; }
  void change(const Vector& x, Vector& y) const;


  /// A row's state in the normal set (`active`): off (its force at its lower bound), on (the law's
  /// branch: Signorini's fixed dof or compliance's spring) or, for a bonded row (adhesion), on the
  /// bond's spring of stiffness a_i (λ_i = a_i (N_i u − g_i), the node separated by less than L_i).
  static constexpr char kOff = 0, kOn = 1, kBonded = 2;
  /// Row i's state for a first iterate from the force λ and the gap left g_i − N_i u.
  char first_state(Eigen::Index i, double lambda, double gap) const;

  /// Each local row's dof k and α in w.
  const std::vector<RotatedRow>& rows() const { return rows_; }
  Eigen::Index n_rows() const { return static_cast<Eigen::Index>(rows_.size()); }
  /// c_i of the update rule λ_i − lower_i + c_i (N_i u − g_i) > 0.
  double scale(Eigen::Index i) const { return scale_[static_cast<std::size_t>(i)]; }
  /// The lower bound of row i's force (ContactConstraints::lower_of): an inactive row's force.
  double lower(Eigen::Index i) const { return lower_[static_cast<std::size_t>(i)]; }
  /// 1/k of an active compliant row's spring, 0 for a rigid row.
  double spring(std::size_t i) const { return spring_[i]; }
  bool compliant(Eigen::Index i) const { return !spring_.empty() && spring_[static_cast<std::size_t>(i)] > 0; }
  /// g_i − N_i u, in the rotated dofs.
  double gap_left(const Vector& w, Eigen::Index i) const { return c_.gap[i] - rows_[i].alpha * w[rows_[i].dof]; }
  /// Pᵀx (a force into w's dofs), P⁻¹u and Pw; without pairs P is the reflections Q = Qᵀ = Q⁻¹.
  Vector rotate(const Vector& x) const {
    return basis_.pairs() ? Vector(basis_.P.transpose() * x) : basis_.P.size() ? Vector(basis_.P * x) : x;
  }
  Vector to_basis(const Vector& u) const {
    return basis_.pairs() ? Vector(basis_.P_inverse * u) : basis_.P.size() ? Vector(basis_.P * u) : u;
  }
  Vector unrotate(const Vector& w) const { return basis_.P.size() ? Vector(basis_.P * w) : w; }

  /// One iteration's solve with the `active` set (factorized for it if needed) and its normal update.
  struct Iterate {
    Vector r;                // b − K_rot w: the reactions
    std::vector<char> next;  // the next normal set
    double most_negative = 0;
    Eigen::Index worst = -1;
    double residual_left = 0;  // the solve's equilibrium residual, at most (‖·‖₂; 0: solved exactly)
    bool failed = false;       // the coupled solve's GMRES failed: w unchanged, the iteration stops
  };
  Iterate iterate(const std::vector<char>& active, const Vector& b, Vector& w, bool tight, Vector& lambda_local,
                  ContactReport& rep, TangentialPart& tangents);
  /// Monotone updates once a set came back: add every violated row, release only the row with
  /// the most negative force (the classical active-set step, which cannot cycle). Collective.
  void release_one(const std::vector<char>& active, std::vector<char>& next, double most_negative,
                   Eigen::Index worst) const;

 private:
  struct Solved {
    double residual_left = 0;
    bool failed = false;
  };
  int factorize_for(const std::vector<char>& active, const TangentialPart& tangents);
  Solved solve_constrained(const std::vector<char>& active, const Vector& b, Vector& w, bool tight,
                           TangentialPart& tangents);
  double loose_tolerance(const Vector& rhs, const Vector& w) const;
  void normal_update(const std::vector<char>& active, const Vector& w, const Vector& r, Vector& lambda_local,
                     std::vector<char>& next, double& most_negative, Eigen::Index& worst,
                     const TangentialPart& tangents) const;
  SparseMatrix owned_matrix(const std::vector<Eigen::Triplet<double>>& entries) const;

  std::shared_ptr<const la::SpdOperator> K_, K_rot_;
  std::shared_ptr<la::LinearSolver> factor_;
  ContactConstraints c_;
  ContactBasis basis_;             // u = P w (P empty: no row needs a rotation)
  std::vector<RotatedRow> rows_;   // per local row
  std::vector<double> scale_;      // c_i of the update rule
  std::vector<double> spring_;     // per local row: 1/k of an active compliant row's spring, 0 for a rigid row
  std::vector<double> lower_;      // per local row: its force's lower bound (0 but for a law with tension, or
                                   // the step's bond: ContactConstraints::lower_of, again at set_bond)
  /// The next state of a bonded row (c_.bond_of(i) > 0) from its force and penetration d = N_i u − g_i.
  char bonded_state(Eigen::Index i, double lambda, double d) const;
  Vector diagonal_;                // K_rot's
  std::shared_ptr<la::SpdOperator> A_;  // K_rot (+ springs) with the factored set's rows fixed
  bool keep_factor() const;
  std::vector<char> fixed_;           // the fixed dofs now
  std::vector<char> factored_fixed_;  // ... and those the factor holds
  std::vector<Eigen::Triplet<double>> factored_springs_;  // the springs the factor holds
  SparseMatrix springs_now_;          // the springs now where they differ (changed_)
  bool changed_ = false;              // A now differs from A (a direct solver's factor kept)
  void count_perturbed(int products, double reduction);
  double factor_solves_ = 0;          // a factorization's cost in solves (keep_factor)
  double excess_products_ = 0;        // GMRES's products since the factor beyond a fresh one's
};

class PrimalWarmStart;

/// One solve of the primal contact problem over the operator, chosen once where the solver is built
/// (make_primal_active_set_solver): the frictionless active-set Newton method (primal_active_set.cpp)
/// or HSW's frictional one (PrimalFrictionIteration).
class PrimalIteration {
 public:
  virtual ~PrimalIteration() = default;
  /// The arguments as ContactSolver::solve's; `warm`: the solver's last answers; `max_iterations`: solves
  /// before it gives up (converged = false).
  virtual ContactReport solve(PrimalOperator& op, PrimalWarmStart& warm, int max_iterations, const Vector& F,
                              Vector& u, Vector& lambda) = 0;
  /// Its max_iterations unless the caller gives one (kPrimalMaxIterations, kPrimalFrictionMaxIterations).
  virtual int most_iterations() const = 0;
};

/// The first iterate of a solve from the solver's last answers (the warm start).
class PrimalWarmStart {
 public:
  /// The first iterate w (rotated): u, or, when the caller continues from this solver's last
  /// answer, the extrapolation of the last two answers (a step's load and gap change smoothly):
  /// foundation-3d n = 8, 100 steps on CHOLMOD, 127 → 105 solves; n = 20, 20 steps on CG + GAMG,
  /// 68 → 60 (loose ones included).
  Vector start_point(const PrimalOperator& op, const Vector& F, const Vector& u) const;
  /// Whether the caller continues from this solver's last answer (collective).
  bool continuing(const la::Comm& comm, const Vector& u) const {
    return comm.all(u.size() == u_last_.size() && u == u_last_);
  }
  /// Keeps the answer w and returns it as u = P w.
  void keep_answer(const PrimalOperator& op, const Vector& w, Vector& u);

 private:
  Vector w_last_, w_before_;  // the last two answers (rotated): the extrapolated warm start
  Vector u_last_;             // the last answer as returned (is the caller continuing from it?)
};

}  // namespace vpc
