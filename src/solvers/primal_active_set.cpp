#include "solvers/primal_active_set.hpp"

#include "core/error.hpp"
#include "solvers/active_set_history.hpp"
#include "solvers/anderson_mixing.hpp"
#include "solvers/primal_friction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace vpc {

namespace {

class PrimalActiveSetSolver final : public ContactSolver {
 public:
  PrimalActiveSetSolver(std::shared_ptr<const la::SpdOperator> K, std::shared_ptr<const la::SpdOperator> K_rot,
                        std::shared_ptr<la::LinearSolver> factor, ContactConstraints c, int max_iterations,
                        double friction_tolerance)
      : force_tolerance_(friction_tolerance), max_iterations_(max_iterations > 0 ? max_iterations
                        : c.frictional()  ? kPrimalFrictionMaxIterations
                                          : kPrimalMaxIterations),
        K_(std::move(K)), K_rot_(K_rot ? std::move(K_rot) : K_), factor_(std::move(factor)), c_(std::move(c)),
        Q_(contact_reflections(c_.N)), rows_(rotated_rows(c_.N)) {
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(rows_.size()) && !c_.laws.empty(); ++i) {
      const ContactLaw& law = c_.law_of(i);
      require(law.rigid() || law.linear(),
              "contact solver 'primal-active-set' solves Signorini and linear normal compliance rows; a {} needs "
              "'active-set'",
              law.kind());
      // An active compliant row is the spring of the law's linearization (exact for a linear law).
      spring_.push_back(law.rigid() ? 0.0 : law.spring_compliance(c_.compliance[i]));
    }
    require(Q_.size() == 0 || K_rot_ != K_, "internal: the primal contact solver needs Q K Q for rotated rows");
    // c_i of the update rule λ_i + c_i (N_i u − g_i) > 0: K's stiffness at the row's dof, per unit of N_i u.
    diagonal_ = K_rot_->diagonal();
    const Vector& d = diagonal_;
    for (const RotatedRow& r : rows_) scale_.push_back(d[r.dof] / (r.alpha * r.alpha));
    if (c_.frictional()) friction_.emplace(c_, diagonal_);
  }

  ContactReport solve(const Vector& F, Vector& u, Vector& lambda) override {
    if (friction_) return solve_frictional(F, u, lambda);
    const auto rows = static_cast<Eigen::Index>(rows_.size());
    const la::Comm& comm = K_->comm();
    const Vector b = rotate(F);
    Vector w = start_point(F, u);
    const Vector lambda_in = lambda.size() == c_.m ? local_rows(c_, lambda) : Vector(Vector::Zero(rows));
    std::vector<char> active(static_cast<size_t>(rows));
    for (Eigen::Index i = 0; i < rows; ++i) active[i] = lambda_in[i] > 0 || gap_left(w, i) < 0;
    Vector lambda_local = Vector::Zero(rows);
    ActiveSetHistory history;  // the active sets met in this solve
    ContactReport rep;
    bool monotone = false, converged = false;
    // An iterative solver finds the set with loose solves (the set decides by signs, not
    // digits), then confirms it with one at its own tolerance (an inexact semismooth Newton
    // method); a direct one is exact every time.
    bool tight = !factor_->iterative();
    for (int it = 0; it < max_iterations_ && !converged; ++it) {
      auto [r, next, most_negative, worst] = iterate(active, b, w, tight, lambda_local, rep);
      if (comm.all(next == active)) {
        converged = tight;
        tight = true;
        continue;
      }
      if (monotone) {
        release_one(active, next, most_negative, worst);
        if (comm.all(next == active)) {  // what the rule would still release has λ = 0: KKT holds
          converged = tight;
          tight = true;
          continue;
        }
      }
      if (history.came_back(next, comm) && !monotone) {
        monotone = true;
        ++rep.cycles;
      }
      active = std::move(next);
    }
    keep_answer(w, u);
    lambda = replicate(comm, c_, lambda_local);
    ContactReport out = contact_report(*K_, c_, F, u, lambda, converged, rep.iterations);
    out.factorizations = rep.factorizations;
    out.cycles = rep.cycles;
    return out;
  }

  /// With friction (primal_friction.hpp): Coulomb as a fixed point of the bound s = tresca +
  /// μ λ_ν(s) over Tresca problems (SPEC §7), each solved exactly by Newton's iteration. Within a
  /// Tresca problem (s frozen) the normal set is updated as without friction and the stick set
  /// and the slip rows' linearizations by HSW's rule (primal_friction.hpp); once the directions
  /// moved less than kInnerShare of the bound's last change, each iterate also updates the bound.
  /// It is solved when both sets hold and the slip forces used equal the updated ones to
  /// the friction tolerance of the force scale (max(‖QF‖∞, ‖λ_ν‖∞)). Then s is recomputed from its λ_ν:
  /// Coulomb holds when it changed by less than the friction tolerance, else the next bound is its
  /// Anderson-accelerated update. On an iterative solver the forces count as
  /// settled also when they stop contracting at its accuracy (below kNoiseCeiling and less than
  /// halved by a tight solve). The first bound: tresca + μ (λ_ν + c (N u − g))₊ (HSW's) after
  /// the first solve, also with a warm start (the last step's λ_ν is the last load's: a 2D block
  /// pressed down, 40 x 20 cells, 20 steps: 18–26 → 12 solves a step, 131 → 62 factorizations).
  /// Cycling within a Tresca problem: once a pair of sets comes back (ActiveSetHistory), updates
  /// turn monotone: every violated normal row is added and only the most negative force released
  /// (as without friction); every slip row that would stick sticks, but only the stick row
  /// furthest beyond its bound starts to slip; slip directions keep being updated. A new bound is
  /// a new problem (the history restarts). No convergence in max_iterations solves (Coulomb's
  /// fixed point has no solution, or too large a μ): converged = false, the step fails
  /// (contact_failure) and the step control retries a smaller step.
  ContactReport solve_frictional(const Vector& F, Vector& u, Vector& lambda) {
    const auto rows = static_cast<Eigen::Index>(rows_.size());
    const la::Comm& comm = K_->comm();
    const Vector b = rotate(F);
    Vector w = start_point(F, u);
    const bool warm = lambda.size() == static_cast<Eigen::Index>(c_.m) * c_.block;
    Vector normal_in = warm ? local_normal(c_, lambda) : Vector(Vector::Zero(rows));
    Vector tangential_in = warm ? local_tangential(c_, lambda) : Vector();
    if (warm && continuing(u) && forces_before_.size() == normal_in.size() + tangential_in.size()) {
      // The forces extrapolated as w is (a step's load changes smoothly).
      const Vector forces = 2 * forces_last_ - forces_before_;
      normal_in = forces.head(rows);
      tangential_in = forces.tail(tangential_in.size());
    }
    std::vector<char> active(static_cast<size_t>(rows));
    for (Eigen::Index i = 0; i < rows; ++i) active[i] = normal_in[i] > 0 || gap_left(w, i) < 0;
    friction_->start(c_, active, normal_in, tangential_in);
    Vector bound = Vector::Zero(rows);  // s of the Tresca problem being solved, from the first solve
    bool bound_known = false;
    AndersonMixing coulomb(kAndersonDepth);
    Vector lambda_local = Vector::Zero(rows), tangential;
    auto history = std::make_unique<ActiveSetHistory>();
    ContactReport rep;
    bool monotone = false, converged = false, tight = !factor_->iterative();
    const double inf = std::numeric_limits<double>::infinity();
    double last_direction = inf, last_bound = inf;  // the last changes after tight solves
    double bound_change = inf;                       // of the last Tresca problem's bound
    const double b_scale = comm.max(b.size() ? b.cwiseAbs().maxCoeff() : 0.0);
    auto settled = [&](double change, double& last) {
      const bool yes = change <= force_tolerance_ ||
                       (tight && factor_->iterative() && change <= kNoiseCeiling && change > 0.5 * last);
      if (tight) last = change;
      return yes;
    };
    for (int it = 0; it < max_iterations_ && !converged; ++it) {
      // An iterative solver reduces each correction's residual by a fixed share (inexact Newton:
      // each solve starts from the true residual of the last iterate, so the errors do not add up;
      // the answer's equilibrium residual must be within the friction tolerance: residual_left_).
      // To its own 1e-12 every time, foundation-3d n = 10 took 29 CG iterations a solve.
      // (Frictional foundation-3d on CG + GAMG, 100 steps, CG iterations over the run: n = 10
      // 6,760 with a share of 1e-3, 5,840 with 1e-2, 5,437 with 3e-2; n = 20 9,935, 8,262, 8,067,
      // but 3e-2 took 10% more solves. The first session's 22,314 at n = 10 were to 1e-12.)
      forcing_ = factor_->iterative() && tight ? kForcing : 0.0;
      auto [r, next, most_negative, worst] = iterate(active, b, w, tight, lambda_local, rep);
      if (monotone) release_one(active, next, most_negative, worst);
      tangential = friction_->forces(r);
      if (!bound_known) {  // HSW: λ_ν + c_ν (N u − g), ≥ 0, on the next set
        for (Eigen::Index i = 0; i < rows; ++i) {
          const double gap = gap_left(w, i);
          bound[i] = c_.bound(i, !next[i]         ? 0.0
                                 : compliant(i) ? -gap / spring_[static_cast<std::size_t>(i)]
                                                : lambda_local[i] - scale_[i] * gap);
        }
        bound_known = true;
      }
      // c's secant step while the slip forces still move much; then fixed, for Anderson's mixing
      // (a 3D block pressed, ν = 0.3: with it updated to the end, a step stalled near 1e-9).
      friction_->secant(c_, w, tangential, comm, last_direction > kSecantUntil);
      PrimalFriction::Next up = friction_->next(c_, w, tangential, bound);
      if (monotone) friction_->slip_one(up, comm);
      const double scale = std::max({b_scale, comm.max(lambda_local.size() ? lambda_local.cwiseAbs().maxCoeff() : 0.0),
                                     std::numeric_limits<double>::min()});
      if (!comm.all(next == active) || !comm.all(up.stick == friction_->stick())) {
        if (history->came_back(contact_sets(next, up.stick), comm) && !monotone) {
          monotone = true;
          ++rep.cycles;
        }
        active = std::move(next);
        friction_->take(std::move(up));
        last_direction = inf;
        continue;
      }
      // Within a Tresca problem the slip directions are iterated only to a share of the bound's last
      // change (an inexact inner solve; 3D partial slip on the test block: 93 → 38 solves, 3D full slip 47 → 19), to
      // the friction tolerance at the end.
      const double direction_change = comm.max(up.change) / scale;
      const bool was_tight = tight, directions_held = settled(direction_change, last_direction);
      tight = true;  // sets found: tight solves from here on (an iterative solver's forces need them)
      if (!directions_held && direction_change > kInnerShare * bound_change) {
        friction_->take(std::move(up));  // Newton's next linearization
        continue;
      }
      // This Tresca problem is solved: Coulomb's bound from its λ_ν.
      Vector coulomb_bound(rows);
      for (Eigen::Index i = 0; i < rows; ++i) coulomb_bound[i] = c_.bound(i, active[i] ? lambda_local[i] : 0.0);
      bound_change = comm.max(bound_moved(coulomb_bound, bound, tangential)) / scale;
      const bool bound_held = settled(bound_change, last_bound);
      if (bound_held && directions_held) {
        // ... and the last correction's equilibrium residual (an inexact solve's, bounded by its
        // forcing) within the same tolerance: from a loose iterate, one correction leaves kForcing of
        // the loose residual (a pressed block that sticks: equilibrium 9.8e-9 against the step's 1e-8).
        converged = was_tight && residual_left_ <= force_tolerance_ * scale;
        continue;
      }
      if (bound_held) {  // the directions still to settle
        friction_->take(std::move(up));
        continue;
      }
      // A loose solve's λ_ν (an iterative solver's first, finding the sets) is a guess, not G(s):
      // in Anderson's history it would be the one small residual and hold the bound near itself
      // (foundation-3d sliding: 1.6e-7 three times over); the first tight solve updates the bound
      // at once. Frictional foundation-3d n = 10 on CG + GAMG, 100 steps: 788 → 643 solves.
      bound = was_tight ? coulomb.next(comm, bound, coulomb_bound) : coulomb_bound;
      if (!was_tight) bound_change = inf;
      for (Eigen::Index i = 0; i < rows; ++i) bound[i] = std::max(bound[i], c_.tresca[i]);  // μ λ_ν ≥ 0
      friction_->take(std::move(up));
      friction_->rescale(bound);
      history = std::make_unique<ActiveSetHistory>();
      monotone = false;
      last_direction = inf;
    }
    keep_answer(w, u);
    forces_before_ = std::move(forces_last_);
    forces_last_.resize(rows + tangential.size());
    forces_last_ << lambda_local, tangential;
    lambda = replicate_blocks(comm, c_, lambda_local, tangential);
    ContactReport out = contact_report(*K_, c_, F, u, lambda, converged, rep.iterations);
    out.factorizations = rep.factorizations;
    out.cycles = rep.cycles;
    return out;
  }

  void set_gap(const Vector& gap) override { c_.gap = checked_gap(c_, gap); }
  void set_friction(const Vector& tresca, const Vector& shift) override { set_friction_data(c_, tresca, shift); }
  const la::LinearSolver* own_factor() const override { return factor_.get(); }
  std::string name() const override { return "primal-active-set"; }
  std::string describe() const override {
    return "primal active set on u (K with the active rows as constraints; refactorized when the set changes)";
  }

 private:
  const double force_tolerance_;  // ContactSolverOptions::friction_tolerance
  const int max_iterations_;
  // Slip forces within force_tolerance_ of the force scale (max(‖QF‖∞, ‖λ_ν‖∞)) count as settled; on an
  // iterative solver also forces that no longer halve below kNoiseCeiling (its accuracy).
  // (1e-8 let a run's friction-bound residual reach 5.2e-9 against the step's tolerance 1e-8:
  // foundation-3d n = 20 on CG + GAMG; the inexact corrections improve the accuracy each iterate.)
  static constexpr double kNoiseCeiling = 1e-10;
  static constexpr int kAndersonDepth = 8;
  static constexpr double kInnerShare = 0.1, kSecantUntil = 1e-6;
  static constexpr double kForcing = 1e-2, kLaggedSpringShare = 0.5;
  // Loose enough that finding a set costs a few iterations, tight enough that the signs
  // rarely mislead (foundation-3d n = 40, 5 steps on CG + GAMG: 1e-6 → 3.2 s a step,
  // 1e-4 → 3.0 s, 1e-3 → up to 25 set iterations in a step).
  static constexpr double kLooseTolerance = 1e-4;
  static constexpr double kLooseReduction = 1e-2, kLooseFloor = 1e-9;

  /// How far Coulomb's bound moved (|G(s) − s|, largest) over the rows where it acts: the slip
  /// rows (their force is s n), and the stick rows that it could turn to slip (their |λ_τ| closer
  /// to s than the move). A stick row further inside its disc sticks under either bound, and the
  /// Tresca problem's answer is then Coulomb's there whatever its s; a pressed block whose contact
  /// sticks then stops once its sets hold (frictional foundation-3d n = 10 on CG + GAMG, 100 steps:
  /// 5.1 → 4.8 solves a step while pressed).
  double bound_moved(const Vector& coulomb_bound, const Vector& bound, const Vector& tangential) const {
    const auto t = static_cast<Eigen::Index>(c_.block - 1);
    double moved = 0;
    for (Eigen::Index i = 0; i < coulomb_bound.size(); ++i) {
      const double d = std::abs(coulomb_bound[i] - bound[i]);
      if (friction_->stick()[static_cast<std::size_t>(i)] && bound[i] - tangential.segment(i * t, t).norm() > d) continue;
      moved = std::max(moved, d);
    }
    return moved;
  }
  bool compliant(Eigen::Index i) const { return !spring_.empty() && spring_[static_cast<std::size_t>(i)] > 0; }
  /// g_i − N_i u, in the rotated dofs.
  double gap_left(const Vector& w, Eigen::Index i) const { return c_.gap[i] - rows_[i].alpha * w[rows_[i].dof]; }
  Vector rotate(const Vector& x) const { return Q_.size() ? Vector(Q_ * x) : x; }
  Vector unrotate(const Vector& w) const { return rotate(w); }  // Q = Q⁻¹

  /// Factorizes K_rot with `active`'s constraints unless the factor already holds them. Returns 1 if it did.
  int factorize_for(const std::vector<char>& active) {
    const la::Comm& comm = K_->comm();
    std::vector<Eigen::Triplet<double>> springs;
    if (friction_) friction_->springs(springs);  // Newton's springs across the slip directions
    spring_change_ = SparseMatrix();
    if (A_ && comm.all(active == factored_) && (!friction_ || comm.all(friction_->stick() == factored_stick_))) {
      std::vector<Eigen::Triplet<double>> factored;
      if (friction_) friction_->factored_springs(factored);
      if (!friction_ || comm.all(same(springs, factored))) return 0;
      if (!factor_->iterative() && comm.all(friction_->factored_serves(kLaggedSpringShare))) {
        // A direct solver keeps its factor while the sets hold (a numeric factorization costs some
        // twenty solves): the springs' change since it goes to the right-hand side, lagged one
        // iterate (solve_constrained). Foundation-3d n = 20 on CHOLMOD, 100 steps: 720
        // factorizations and 1,494 s with a factorization at every iterate.
        spring_change_ = owned_matrix(springs) - owned_matrix(factored);
        return 0;
      }
    }
    std::vector<char> fixed(static_cast<size_t>(K_->n_owned()), 0);
    if (friction_) {
      friction_->fix(fixed);
      friction_->mark_factored();
      factored_stick_ = friction_->stick();
    }
    for (size_t i = 0; i < rows_.size(); ++i) {
      if (!active[i]) continue;
      if (compliant(static_cast<Eigen::Index>(i)))
        springs.emplace_back(rows_[i].dof, rows_[i].dof, rows_[i].alpha * rows_[i].alpha / spring_[i]);
      else
        fixed[rows_[i].dof] = 1;
    }
    std::shared_ptr<const la::SpdOperator> base = K_rot_;
    if (comm.any(!springs.empty())) {
      SparseMatrix D(K_->n_owned(), K_->n_owned());
      D.setFromTriplets(springs.begin(), springs.end());
      base = base->plus(D);
    }
    // The factor (or the preconditioner) keeps a reference to its operator: the old one
    // lives until the new one is in place.
    std::shared_ptr<const la::SpdOperator> next = base->with_fixed(fixed);
    if (A_)
      factor_->refactorize(*next, "elastic stiffness K with the active contact rows");
    else
      factor_->factorize(*next, "elastic stiffness K with the active contact rows");
    A_ = std::move(next);
    factored_ = active;
    fixed_ = std::move(fixed);
    return 1;
  }
  SparseMatrix owned_matrix(const std::vector<Eigen::Triplet<double>>& entries) const {
    SparseMatrix D(K_->n_owned(), K_->n_owned());
    D.setFromTriplets(entries.begin(), entries.end());
    return D;
  }
  static bool same(const std::vector<Eigen::Triplet<double>>& a, const std::vector<Eigen::Triplet<double>>& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const auto& x, const auto& y) {
      return x.row() == y.row() && x.col() == y.col() && x.value() == y.value();
    });
  }

  /// w = the solution of K_rot w = b with the active rows: w_k = g/α on Signorini rows
  /// (the others moved to the right-hand side), springs on the compliance rows.
  void solve_constrained(const std::vector<char>& active, const Vector& b, Vector& w, bool tight) const {
    Vector fixed_values = Vector::Zero(b.size());
    Vector rhs = b;
    for (size_t i = 0; i < rows_.size(); ++i) {
      if (!active[i]) continue;
      const auto e = static_cast<Eigen::Index>(i);
      if (compliant(e))
        rhs[rows_[i].dof] += rows_[i].alpha * c_.gap[e] / spring_[i];
      else
        fixed_values[rows_[i].dof] = c_.gap[e] / rows_[i].alpha;
    }
    if (friction_) friction_->load(c_, rhs, fixed_values);
    if (spring_change_.nonZeros() > 0) rhs -= spring_change_ * w;  // (K + M_factored) w = … − (M − M_factored) w_last
    Vector coupling;
    K_rot_->mult(fixed_values, coupling);
    rhs -= coupling;
    for (Eigen::Index j = 0; j < rhs.size(); ++j)
      if (fixed_[j]) {  // the fixed rows of A keep K_rot's diagonal (la::SpdOperator::with_fixed)
        w[j] = fixed_values[j];
        rhs[j] = diagonal_[j] * fixed_values[j];
      }
    factor_->set_relative_tolerance(tight ? 0.0 : loose_tolerance(rhs, w));
    if (friction_ && tight && factor_->iterative()) {
      // With friction the fixed rows (stick dofs at h, which grows with the slip) can dominate
      // ‖rhs‖, against which an iterative solver's tolerance is relative: solve for the
      // correction, whose right-hand side is the residual (0 on the fixed rows). (Cattaneo–Mindlin
      // on CG + GAMG: equilibrium residual 2.9e-8 above the tolerance 1e-8 without.)
      Vector r, delta = Vector::Zero(w.size());
      A_->residual(rhs, w, r);
      if (forcing_ > 0) factor_->set_relative_tolerance(forcing_);
      factor_->solve(r, delta);
      w += delta;
      residual_left_ = forcing_ * std::sqrt(K_->comm().sum(r.squaredNorm()));  // ‖r − Aδ‖₂ ≤ forcing ‖r‖₂
      return;
    }
    residual_left_ = 0;  // a direct solve (a loose one never ends the iteration: was_tight)
    factor_->solve(rhs, w);
  }

  /// A loose solve stops at kLooseTolerance ‖rhs‖ or at kLooseReduction of its initial
  /// residual, whichever is smaller: a solve must answer a set change even when the guess
  /// already meets kLooseTolerance (else the set flips back and forth on an unchanged w).
  double loose_tolerance(const Vector& rhs, const Vector& w) const {
    Vector r;
    A_->residual(rhs, w, r);
    double norms[2] = {r.squaredNorm(), rhs.squaredNorm()};
    K_->comm().sum(norms, 2);
    if (!(norms[1] > 0)) return 0.0;
    const double rtol = std::min(kLooseTolerance, kLooseReduction * std::sqrt(norms[0] / norms[1]));
    return rtol > kLooseFloor ? rtol : 0.0;  // that close to the answer, the solver's own tolerance
  }

  /// The first iterate w (rotated): u, or, when the caller continues from this solver's last
  /// answer, the extrapolation of the last two answers (a step's load and gap change smoothly):
  /// foundation-3d n = 8, 100 steps on CHOLMOD, 127 → 105 solves; n = 20, 20 steps on CG + GAMG,
  /// 68 → 60 (loose ones included).
  Vector start_point(const Vector& F, const Vector& u) const {
    Vector w = rotate(u.size() == F.size() ? u : Vector(Vector::Zero(F.size())));
    if (w_before_.size() == w.size() && continuing(u)) w = 2 * w_last_ - w_before_;
    return w;
  }
  /// Whether the caller continues from this solver's last answer (collective).
  bool continuing(const Vector& u) const { return K_->comm().all(u.size() == u_last_.size() && u == u_last_); }
  void keep_answer(const Vector& w, Vector& u) {
    w_before_ = std::move(w_last_);
    w_last_ = w;
    u = unrotate(w);
    u_last_ = u;
  }

  /// One iteration's solve with the `active` set (factorized for it if needed) and its normal update.
  struct Iterate {
    Vector r;                // b − K_rot w: the reactions
    std::vector<char> next;  // the next normal set
    double most_negative = 0;
    Eigen::Index worst = -1;
  };
  Iterate iterate(const std::vector<char>& active, const Vector& b, Vector& w, bool tight, Vector& lambda_local,
                  ContactReport& rep) {
    Iterate x;
    rep.factorizations += factorize_for(active);
    solve_constrained(active, b, w, tight);
    K_rot_->residual(b, w, x.r);
    normal_update(active, w, x.r, lambda_local, x.next, x.most_negative, x.worst);
    ++rep.iterations;
    return x;
  }

  /// λ_ν of the iterate (reaction r = b − K_rot w at an active Signorini row, the spring's force
  /// at a compliant one) and the next normal set by the update rule; `worst`: the active
  /// Signorini row with the most negative force (if below 0).
  void normal_update(const std::vector<char>& active, const Vector& w, const Vector& r, Vector& lambda_local,
                     std::vector<char>& next, double& most_negative, Eigen::Index& worst) const {
    next.assign(active.size(), 0);
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(rows_.size()); ++i) {
      const RotatedRow& row = rows_[i];
      const double gap = gap_left(w, i);
      if (compliant(i)) {  // λ = k (N u − g)₊: active where the row penetrates
        lambda_local[i] = active[i] ? -gap / spring_[static_cast<std::size_t>(i)] : 0.0;
        next[i] = gap < 0;
      } else {
        lambda_local[i] = active[i] ? r[row.dof] / row.alpha : 0.0;
        next[i] = lambda_local[i] - scale_[i] * gap > 0;
        if (active[i] && lambda_local[i] < most_negative) {
          most_negative = lambda_local[i];
          worst = i;
        }
      }
    }
  }

  /// Monotone updates once a set came back: add every violated row, release only the row with
  /// the most negative force (the classical active-set step, which cannot cycle). Collective.
  void release_one(const std::vector<char>& active, std::vector<char>& next, double most_negative,
                   Eigen::Index worst) const {
    const double global_worst = K_->comm().min(most_negative);
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(rows_.size()); ++i)
      if (!compliant(i)) next[i] = active[i] ? !(i == worst && most_negative == global_worst) : next[i];
  }

  std::shared_ptr<const la::SpdOperator> K_, K_rot_;
  std::shared_ptr<la::LinearSolver> factor_;
  ContactConstraints c_;
  SparseMatrix Q_;                 // empty: no row needs a rotation
  std::vector<RotatedRow> rows_;   // per local row
  std::vector<double> scale_;      // c_i of the update rule
  std::vector<double> spring_;     // per local row: 1/k of an active compliant row's spring, 0 for a rigid row
  Vector diagonal_;                // K_rot's
  std::shared_ptr<const la::SpdOperator> A_;  // K_rot (+ springs) with the factored set's rows fixed
  std::vector<char> factored_, fixed_;
  std::optional<PrimalFriction> friction_;  // with friction (block > 1)
  std::vector<char> factored_stick_;        // the stick set the factor holds
  SparseMatrix spring_change_;  // a direct solver's: the springs now less those in its factor
  Vector w_last_, w_before_;  // the last two answers (rotated): the extrapolated warm start
  Vector u_last_;             // the last answer as returned (is the caller continuing from it?)
  double forcing_ = 0;  // with friction and an iterative solver: the relative tolerance of the next correction
  mutable double residual_left_ = 0;  // the last solve's equilibrium residual, at most (‖·‖₂; 0: solved exactly)
  Vector forces_last_, forces_before_;  // with friction: this rank's λ_ν then λ_τ of the last two answers
};

}  // namespace

std::unique_ptr<ContactSolver> make_primal_active_set_solver(std::shared_ptr<const la::SpdOperator> K,
                                                             std::shared_ptr<const la::SpdOperator> K_rot,
                                                             std::shared_ptr<la::LinearSolver> factor,
                                                             ContactConstraints constraints, int max_iterations,
                                                             double friction_tolerance) {
  return std::make_unique<PrimalActiveSetSolver>(std::move(K), std::move(K_rot), std::move(factor),
                                                 std::move(constraints), max_iterations, friction_tolerance);
}

}  // namespace vpc
