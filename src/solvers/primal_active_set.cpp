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
        basis_(contact_basis(c_.N, c_.node_dofs, c_.master_mean)), rows_(basis_.rows) {
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(rows_.size()) && !c_.laws.empty(); ++i) {
      const ContactLaw& law = c_.law_of(i);
      require(law.rigid() || law.linear(),
              "contact solver 'primal-active-set' solves Signorini and linear normal compliance rows; a {} needs "
              "'active-set'",
              law.kind());
      // An active compliant row is the spring of the law's linearization (exact for a linear law).
      spring_.push_back(law.rigid() ? 0.0 : law.spring_compliance(c_.compliance[i]));
    }
    require(basis_.P.size() == 0 || K_rot_ != K_, "internal: the primal contact solver needs Pᵀ K P for rotated rows");
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

  /// With friction (primal_friction.hpp): HSW's semismooth Newton method on Coulomb's law (SPEC
  /// §7) as one iteration. Each iterate solves with the normal set, the stick set and the slip rows'
  /// linearizations, Coulomb's bound μ λ_ν(w) coupled into the matrix at the slip rows in contact
  /// (coupling()); from its answer the normal set is updated as without friction, and the stick
  /// set and the slip directions by HSW's rule with the iterate's own bound tresca + μ (λ_ν + c (N u − g))₊.
  /// It is solved when both sets hold, the slip forces s n of the update equal the iterate's λ_τ to
  /// the friction tolerance of the force scale (max(‖QF‖∞, ‖λ_ν‖∞)), and the last solve's
  /// equilibrium residual is within the same tolerance. On an iterative solver the forces count as
  /// settled also when they stop contracting at its accuracy (below kNoiseCeiling and less than
  /// halved by a tight solve). (Until issue 28's fourth part the bound was an outer fixed point over
  /// Tresca problems: 4–5 tight solves a step for it alone, frictional foundation-3d on CG + GAMG.)
  /// Cycling: once a pair of sets comes back (ActiveSetHistory), updates turn monotone: every
  /// violated normal row is added and only the most negative force released (as without
  /// friction); every slip row that would stick sticks, but only the stick row furthest beyond its
  /// bound starts to slip; slip directions keep being updated. No convergence in max_iterations
  /// solves, or a coupled solve that fails (Coulomb's problem has no solution, or too large a μ):
  /// converged = false, the step fails (contact_failure) and the step control retries a smaller step.
  ContactReport solve_frictional(const Vector& F, Vector& u, Vector& lambda) {
    const auto rows = static_cast<Eigen::Index>(rows_.size());
    const la::Comm& comm = K_->comm();
    const Vector b = rotate(F);
    Vector w = start_point(F, u);
    const bool warm = lambda.size() == static_cast<Eigen::Index>(c_.m) * c_.block;
    Vector normal_in = warm ? local_normal(c_, lambda) : Vector(Vector::Zero(rows));
    Vector tangential_in = warm ? local_tangential(c_, lambda) : Vector();
    const bool extrapolated = warm && continuing(u) && forces_before_.size() == normal_in.size() + tangential_in.size();
    if (extrapolated) {
      // The forces extrapolated as w is (a step's load changes smoothly).
      const Vector forces = 2 * forces_last_ - forces_before_;
      normal_in = forces.head(rows);
      tangential_in = forces.tail(tangential_in.size());
    }
    std::vector<char> active(static_cast<size_t>(rows));
    for (Eigen::Index i = 0; i < rows; ++i) active[i] = normal_in[i] > 0 || gap_left(w, i) < 0;
    friction_->start(c_, active, normal_in, tangential_in);
    if (extrapolated) {
      // Newton's first linearization at the extrapolated start (w, λ), HSW's rule with its bound,
      // instead of the last answer's sets and springs with the extrapolated forces: there the
      // first solve's iterate re-opened the residual by 6x and a sliding step took three
      // linearizations after it (frictional foundation-3d n = 20 on CG + GAMG: the residual of
      // the second linearization 1.2e-3 → 1.6e-5 of the force scale; n = 40, 100 steps, 2 ranks:
      // 6,703 → 6,008 Krylov iterations).
      friction_->take(friction_->next(c_, w, tangential_in, hsw_bound(active, normal_in, w)));
    }
    Vector bound = Vector::Zero(rows);  // Coulomb's bound: the iterate's own, or the lagged Tresca problem's
    // (λ_τ sized from the start: a first coupled solve that fails leaves it as it is.)
    Vector lambda_local = Vector::Zero(rows), tangential = Vector::Zero(rows * (c_.block - 1));
    auto history = std::make_unique<ActiveSetHistory>();
    AndersonMixing coulomb(kAndersonDepth);
    ContactReport rep;
    bool monotone = false, converged = false, tight = !factor_->iterative();
    const double inf = std::numeric_limits<double>::infinity();
    double last_direction = inf, last_bound = inf;  // the last changes after tight solves
    double bound_change = inf;                       // of the last Tresca problem's bound (lagged)
    const double b_scale = comm.max(b.size() ? b.cwiseAbs().maxCoeff() : 0.0);
    force_scale_ = std::max(b_scale, std::numeric_limits<double>::min());
    auto settled = [&](double change, double& last) {
      const bool yes = change <= force_tolerance_ ||
                       (tight && factor_->iterative() && change <= kNoiseCeiling && change > 0.5 * last);
      if (tight) last = change;
      return yes;
    };
    couple_ = true;
    coupled_failed_ = false;
    newton_target_ = 0;
    for (int it = 0; it < max_iterations_ && !converged; ++it) {
      if (couple_ && it == kCoupledIterations) couple_ = false;  // no convergence yet: lag the bound
      auto [r, next, most_negative, worst] = iterate(active, b, w, tight, lambda_local, rep);
      if (coupled_failed_) break;  // Coulomb's linearization singular: not converged
      if (monotone) release_one(active, next, most_negative, worst);
      tangential = friction_->forces(r);
      if (couple_) {
        bound = hsw_bound(next, lambda_local, w, active);
      }
      const double scale = std::max({b_scale, comm.max(lambda_local.size() ? lambda_local.cwiseAbs().maxCoeff() : 0.0),
                                     std::numeric_limits<double>::min()});
      force_scale_ = scale;
      // c's secant step while the slip forces still move much; then fixed (a 3D block pressed,
      // ν = 0.3: with it updated to the end, a step stalled near 1e-9).
      friction_->secant(c_, w, tangential, comm, last_direction > kSecantUntil);
      PrimalFriction::Next up = friction_->next(c_, w, tangential, bound);
      if (monotone) friction_->slip_one(up, comm);
      if (couple_) friction_->slip_before_leaving(c_, active, tangential, bound, next, up);
      if (!comm.all(next == active) || !comm.all(up.stick == friction_->stick())) {
        if (history->came_back(contact_sets(next, up.stick), comm) && !monotone) {
          monotone = true;
          ++rep.cycles;
          // The sets cycle: Coulomb's bound is lagged from here on, each Tresca problem (the
          // bound frozen) solved before the next bound, where the monotone updates cannot cycle.
          // The coupling's nonsymmetric step can swing a row in and out of contact (2D block,
          // μ = 1, full slip; a tilted one, μ = 0.3, partial slip).
          couple_ = false;
        }
        active = std::move(next);
        friction_->take(std::move(up));
        last_direction = inf;
        continue;
      }
      const double direction_change = comm.max(up.change) / scale;
      const bool was_tight = tight, directions_held = settled(direction_change, last_direction);
      tight = true;  // sets found: tight solves from here on (an iterative solver's forces need them)
      if (couple_) {
        // ... and the last correction's equilibrium residual within the same tolerance: from a
        // loose iterate, one correction leaves kForcing of the loose residual (a pressed block
        // that sticks: equilibrium 9.8e-9 against the step's 1e-8).
        converged = directions_held && was_tight && residual_left_ <= force_tolerance_ * scale;
        if (!converged) friction_->take(std::move(up));  // Newton's next linearization
        newton_target_ = direction_change * direction_change;
        continue;
      }
      // Lagged: within a Tresca problem the slip directions are iterated only to a share of the
      // bound's last change (an inexact inner solve; 3D partial slip on the test block: 93 → 38
      // solves, 3D full slip 47 → 19), to the friction tolerance at the end.
      if (!directions_held && direction_change > kInnerShare * bound_change) {
        friction_->take(std::move(up));
        continue;
      }
      // This Tresca problem is solved: Coulomb's bound from its λ_ν.
      Vector coulomb_bound(rows);
      for (Eigen::Index i = 0; i < rows; ++i) coulomb_bound[i] = c_.bound(i, active[i] ? lambda_local[i] : 0.0);
      bound_change = comm.max(bound_moved(coulomb_bound, bound, tangential)) / scale;
      const bool bound_held = settled(bound_change, last_bound);
      if (bound_held && directions_held) {
        converged = was_tight && residual_left_ <= force_tolerance_ * scale;
        continue;
      }
      if (bound_held) {  // the directions still to settle
        friction_->take(std::move(up));
        continue;
      }
      // A loose solve's λ_ν (an iterative solver's first, finding the sets) is a guess, not G(s):
      // in Anderson's history it would be the one small residual and hold the bound near itself.
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
  static constexpr int kAndersonDepth = 8, kCoupledIterations = 40;
  static constexpr double kInnerShare = 0.1, kSecantUntil = 1e-6;
  static constexpr double kForcing = 1e-2, kLeastForcing = 1e-6, kLaggedSpringShare = 0.5;
  // Loose enough that finding a set costs a few iterations, tight enough that the signs
  // rarely mislead (foundation-3d n = 40, 5 steps on CG + GAMG: 1e-6 → 3.2 s a step,
  // 1e-4 → 3.0 s, 1e-3 → up to 25 set iterations in a step).
  static constexpr double kLooseTolerance = 1e-4;
  static constexpr double kLooseReduction = 1e-2, kLooseFloor = 1e-9;

  /// How far Coulomb's bound moved (|G(s) − s|, largest) over the rows where it acts: the slip
  /// rows (their force is s n), and the stick rows that it could turn to slip (their |λ_τ| closer
  /// to s than the move). A stick row further inside its disc sticks under either bound, and the
  /// Tresca problem's answer is then Coulomb's there whatever its s (frictional foundation-3d
  /// n = 10 on CG + GAMG, 100 steps, lagged bound: 5.1 → 4.8 solves a step while pressed).
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
  /// HSW: Coulomb's bound tresca + μ (λ_ν + c_ν (N u − g))₊ on the normal set `in_contact` (λ_ν
  /// `normal` at the rows in contact; a row that enters gets its penetration's force). `held`: the
  /// normal set the iterate w was solved with (empty: none), whose rows have their λ_ν: a Signorini
  /// row N u = g by its constraint, not the round-off of g − α (g/α) that μ would multiply (μ = 1e8:
  /// 1e-8 of the bound), a compliant one its spring's force (or the law's, law_determines).
  Vector hsw_bound(const std::vector<char>& in_contact, const Vector& normal, const Vector& w,
                   const std::vector<char>& held = {}) const {
    Vector bound(normal.size());
    for (Eigen::Index i = 0; i < bound.size(); ++i) {
      const auto k = static_cast<std::size_t>(i);
      const double gap = gap_left(w, i);
      bound[i] = c_.bound(i, !in_contact[k]                   ? 0.0
                             : !held.empty() && held[k] ? normal[i]
                             : compliant(i)             ? -gap / spring_[k]
                                                        : normal[i] - scale_[i] * gap);
    }
    return bound;
  }
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
        // twenty solves): the springs' change since it joins GMRES's operator, the factor its
        // preconditioner (coupling()). Foundation-3d n = 20 on CHOLMOD, 100 steps: 720
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
    const bool with_springs = comm.any(!springs.empty());
    // With friction the springs' pattern is every contact row's tangent block (zeros where a row
    // does not slip), within K_rot's own (a node's dofs couple), so that A_ keeps K_rot's pattern
    // as the slip set changes.
    if (with_springs && friction_) friction_->spring_pattern(springs);
    const SparseMatrix D = with_springs ? owned_matrix(springs) : SparseMatrix();
    // A_ takes the new rows and springs in place where it has K_rot's pattern and the backend can;
    // else a new operator, the old one living until it is in place (the factor or the
    // preconditioner keeps a reference to its operator).
    const char* what = "elastic stiffness K with the active contact rows";
    if (A_ && A_->assign_with_fixed(*K_rot_, fixed, with_springs ? &D : nullptr)) {
      factor_->refactorize(*A_, what);
    } else {
      const std::shared_ptr<const la::SpdOperator> base = with_springs ? K_rot_->plus(D) : K_rot_;
      std::shared_ptr<la::SpdOperator> next = base->with_fixed(fixed);
      if (A_)
        factor_->refactorize(*next, what);
      else
        factor_->factorize(*next, what);
      A_ = std::move(next);
    }
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
  /// (the others moved to the right-hand side), springs on the compliance rows; with friction the
  /// stick and slip rows' conditions (PrimalFriction::load) and Coulomb's coupling (coupling()).
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
    Vector law_rhs = Vector::Zero(b.size());
    const la::Perturbation C = friction_ ? coupling(active, b, rhs, law_rhs) : la::Perturbation();
    if (friction_) friction_->load(c_, coupled_, rhs, fixed_values);
    Vector coupling;
    K_rot_->mult(fixed_values, coupling);
    rhs -= coupling;
    for (Eigen::Index j = 0; j < rhs.size(); ++j)
      if (fixed_[j]) {  // the fixed rows of A keep K_rot's diagonal (la::SpdOperator::with_fixed)
        w[j] = fixed_values[j];
        rhs[j] = diagonal_[j] * fixed_values[j];
      }
    if (weighted_) {  // D rhs, the law rows' own part already over μ (coupling())
      weigh(rhs);
      rhs += law_rhs;
    }
    if (C || (friction_ && tight && factor_->iterative())) {
      // Solved for the correction, whose right-hand side is the residual (0 on the fixed rows):
      // with friction the fixed rows (stick dofs at h, which grows with the slip) can dominate
      // ‖rhs‖, against which an iterative solver's tolerance is relative (Cattaneo–Mindlin on
      // CG + GAMG: equilibrium residual 2.9e-8 above the tolerance 1e-8 without).
      Vector r, delta = Vector::Zero(w.size()), Cw;
      A_->residual(rhs, w, r);
      if (C) C(w, Cw), r -= Cw;
      const double norm = std::sqrt(K_->comm().sum(r.squaredNorm()));
      // Newton's step with Coulomb coupled goes to the friction tolerance, or to the square of the
      // slip directions' last change where that is larger (Newton's quadratic rate: the next change
      // is about that). Frictional foundation-3d n = 10 (20) on CG + GAMG, 100 steps: 3,815 (n = 20
      // not run) iterations with kForcing every time, 3,457 (5,047) to the tolerance, 3,370 (4,966)
      // to the square. A direct solver's GMRES (its iterations are solves with the factor) takes the
      // same target, uncoupled the tolerance; an iterative one reduces each correction's residual
      // by kLeastForcing to kForcing (inexact Newton; lagged: kForcing), or, finding the sets, stops
      // where a loose solve would (loose_tolerance, of ‖rhs‖).
      const double target = std::max(0.5 * force_tolerance_, couple_ ? newton_target_ : 0.0) * force_scale_;
      const double to_target = target / std::max(norm, std::numeric_limits<double>::min());
      double rtol = kForcing;
      if (!factor_->iterative()) {
        rtol = std::clamp(to_target, 1e-14, kForcing);
      } else if (!tight) {
        const double loose = loose_tolerance(rhs, w), rhs_norm = std::sqrt(K_->comm().sum(rhs.squaredNorm()));
        rtol = loose > 0 && norm > 0 ? std::min(kLooseReduction, loose * rhs_norm / norm) : kForcing;
      } else if (couple_) {
        rtol = std::clamp(to_target, kLeastForcing, kForcing);
      }
      if (!C) {
        factor_->set_relative_tolerance(rtol);
        factor_->solve(r, delta);
        w += delta;
        residual_left_ = rtol * norm;  // ‖r − Aδ‖₂ ≤ rtol ‖r‖₂
        return;
      }
      try {
        factor_->solve_perturbed(*A_, C, r, delta, rtol > 0 ? rtol : 1e-12, "elastic stiffness K with Coulomb's coupling");
      } catch (const Error&) {  // GMRES short of its tolerance: w stays, the caller stops
        coupled_failed_ = true;
        return;
      }
      w += delta;
      A_->residual(rhs, w, r);  // the true residual (Eigen's GMRES stops on the preconditioned one)
      C(w, Cw);
      residual_left_ = std::sqrt(K_->comm().sum((r - Cw).squaredNorm()));
      return;
    }
    factor_->set_relative_tolerance(tight ? 0.0 : loose_tolerance(rhs, w));
    residual_left_ = 0;  // a direct solve (a loose one never ends the iteration: was_tight)
    factor_->solve(rhs, w);
  }

  /// Coulomb's bound in Newton's step (HSW's full linearization): at a slip row i in contact with
  /// μ_i > 0 and a direction n_i, the force on tangent dof j is tresca n_ij (PrimalFriction::load)
  /// plus μ_i n_ij λ_ν,i(w), λ_ν a reaction of w: on a Signorini row (b − K_rot w)_ν/α, on a compliant
  /// one (α w_ν − g)/k⁻¹. The w-part is the returned perturbation C of the matrix (nonsymmetric:
  /// row j takes −μ n_j/α times K_rot's row ν), the rest goes to `rhs`. A direct solver's spring
  /// change since its factor (factorize_for) joins C, solved with it by GMRES. Empty: nothing
  /// to add on any rank (a plain solve). Sets coupled_.
  ///
  /// A law_determines row's equation along n_i (−λ_τ(w)·n + tresca + μ λ_ν(w) = 0) is solved over μ:
  /// the system is D (A + C) δ = D r with D = I − (1 − 1/μ) n nᵀ on its tangent dofs (weigh()), its
  /// coupling entries and right-hand side (`law_rhs`) made over μ here (μ n_j/α → n_j/α: D C without
  /// forming μ K, 1e303 at μ = 1e300), and C' = (D − I) A + D (the spring change) + those entries.
  /// That equation carries μ times K w's round-off (μ = 1e8: a residual 5x the friction tolerance,
  /// however far GMRES goes), the scaled one λ_ν's own: the residual that is left is the normal
  /// equilibrium's at the force law_normal_force reports. The equations across n (3D: λ_τ's spring
  /// part) keep their scale.
  la::Perturbation coupling(const std::vector<char>& active, const Vector& b, Vector& rhs, Vector& law_rhs) const {
    const int t = friction_->tangents();
    coupled_.assign(rows_.size(), 0);
    couplings_.clear();
    law_rows_.clear();
    bool signorini = false;
    for (size_t i = 0; i < rows_.size(); ++i) {
      const auto e = static_cast<Eigen::Index>(i);
      if (!couple_ || !active[i] || friction_->stick()[i] || !(c_.mu[e] > 0) || friction_->direction(i).isZero(0.0)) continue;
      // At its shear limit the bound does not move with λ_ν: the force s n stays a load.
      if (c_.limit.size() > 0 && friction_->slip_force(i).norm() >= (1 - 1e-12) * c_.limit[e]) continue;
      coupled_[i] = 1;
      const RotatedRow& row = rows_[i];
      const bool law = law_determines(e);
      if (law) law_rows_.push_back({{}, Vector::Zero(t), 1 / c_.mu[e]});
      for (int j = 0; j < t; ++j) {
        const int dof = friction_->tangent_dof(i, j);
        if (law) {
          law_rows_.back().dofs.push_back(dof);
          if (dof >= 0) law_rows_.back().n[j] = friction_->direction(i)[j];
        }
        // μ n_j, over μ at a law row (D's factor along n; D n = n/μ)
        const double mu_n = (law ? 1.0 : c_.mu[e]) * friction_->direction(i)[j];
        if (dof < 0 || mu_n == 0) continue;
        Vector& load = law ? law_rhs : rhs;
        if (compliant(e)) {
          couplings_.push_back({dof, row.dof, mu_n * row.alpha / spring_[i], false});
          load[dof] += mu_n * c_.gap[e] / spring_[i];
        } else {
          couplings_.push_back({dof, row.dof, -mu_n / row.alpha, true});
          load[dof] -= mu_n / row.alpha * b[row.dof];
          signorini = true;
        }
      }
    }
    const la::Comm& comm = K_->comm();
    weighted_ = comm.any(!law_rows_.empty());
    if (!comm.any(!couplings_.empty() || spring_change_.nonZeros() > 0)) return {};
    // K_rot's normal rows at the coupled Signorini rows only (collective): with the whole product
    // a GMRES iteration cost 1.8 CG iterations (frictional foundation-3d n = 40, 2 ranks).
    la::RowProduct normal_rows;
    if (comm.any(signorini)) {
      std::vector<int> dofs;
      for (const Coupling& c : couplings_)
        if (c.reaction) dofs.push_back(c.normal);
      std::sort(dofs.begin(), dofs.end());
      dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end());
      for (Coupling& c : couplings_)
        if (c.reaction) c.normal = static_cast<int>(std::lower_bound(dofs.begin(), dofs.end(), c.normal) - dofs.begin());
      normal_rows = K_rot_->rows(dofs);
    }
    return [this, normal_rows](const Vector& x, Vector& y) {
      y = Vector::Zero(x.size());
      Vector Kx;
      if (normal_rows) normal_rows(x, Kx);
      for (const Coupling& c : couplings_) y[c.tangent] += c.coefficient * (c.reaction ? Kx[c.normal] : x[c.normal]);
      if (!weighted_) {
        if (spring_change_.nonZeros() > 0) y += spring_change_ * x;
        return;
      }
      Vector Ax, v;  // (D − I) A x + D (spring change) x (collective: A's product)
      A_->mult(x, Ax);
      v = spring_change_.nonZeros() > 0 ? Vector(Ax + spring_change_ * x) : Ax;
      weigh(v);
      y += v - Ax;
    };
  }

  /// y ← D y (coupling()): at each law row's tangent dofs the part along n over μ (as (y − (y·n) n) +
  /// (y·n)/μ n: 1 − 1/μ is 1 in floating point at μ = 1e300, and D would be singular).
  void weigh(Vector& y) const {
    for (const LawRow& x : law_rows_) {
      double along = 0;
      for (std::size_t j = 0; j < x.dofs.size(); ++j)
        if (x.dofs[j] >= 0) along += x.n[static_cast<Eigen::Index>(j)] * y[x.dofs[j]];
      for (std::size_t j = 0; j < x.dofs.size(); ++j)
        if (const int dof = x.dofs[j]; dof >= 0) {
          const double n = x.n[static_cast<Eigen::Index>(j)];
          y[dof] = (y[dof] - along * n) + x.inverse * along * n;
        }
    }
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
    Vector w = to_basis(u.size() == F.size() ? u : Vector(Vector::Zero(F.size())));
    // (continuing is collective: called on every rank, also one that owns no dofs, where the
    // sizes would agree trivially.)
    const bool extrapolate = continuing(u) && w_before_.size() == w.size();
    if (extrapolate) w = 2 * w_last_ - w_before_;
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
        lambda_local[i] = !active[i] ? 0.0 : law_determines(i) ? law_normal_force(i, r) : -gap / spring_[static_cast<std::size_t>(i)];
        next[i] = gap < 0;
      } else {
        lambda_local[i] = !active[i] ? 0.0 : law_determines(i) ? law_normal_force(i, r) : r[row.dof] / row.alpha;
        next[i] = lambda_local[i] - scale_[i] * gap > 0;
        if (active[i] && lambda_local[i] < most_negative) {
          most_negative = lambda_local[i];
          worst = i;
        }
      }
    }
  }

  /// Whether row i's λ_ν is the one its slip law's row gives rather than its reaction (or its
  /// spring's force): at a row whose bound was coupled in the last solve (λ_τ = (tresca + μ λ_ν) n,
  /// one of its equations) with μ > 1. Both are the same λ_ν up to the solve's residual, but the
  /// reaction (b − K_rot w)_ν carries K w's round-off (the spring g − α w_ν's), which μ λ_ν multiplies
  /// into the bound (μ = 1e8: 2e-8 of the force scale, above the friction tolerance whatever the
  /// solve), while the law's row divides λ_τ's by μ.
  bool law_determines(Eigen::Index i) const {
    return friction_ && static_cast<std::size_t>(i) < coupled_.size() && coupled_[static_cast<std::size_t>(i)] &&
           c_.mu[i] > 1;
  }
  /// λ_ν = (λ_τ · n − tresca)/μ with λ_τ the reaction r at the row's tangent dofs.
  double law_normal_force(Eigen::Index i, const Vector& r) const {
    const auto row = static_cast<std::size_t>(i);
    double along = 0;
    for (int j = 0; j < friction_->tangents(); ++j)
      if (const int dof = friction_->tangent_dof(row, j); dof >= 0) along += friction_->direction(row)[j] * r[dof];
    return (along - c_.tresca[i]) / c_.mu[i];
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
  ContactBasis basis_;             // u = P w (P empty: no row needs a rotation)
  std::vector<RotatedRow> rows_;   // per local row
  std::vector<double> scale_;      // c_i of the update rule
  std::vector<double> spring_;     // per local row: 1/k of an active compliant row's spring, 0 for a rigid row
  Vector diagonal_;                // K_rot's
  std::shared_ptr<la::SpdOperator> A_;  // K_rot (+ springs) with the factored set's rows fixed
  std::vector<char> factored_, fixed_;
  std::optional<PrimalFriction> friction_;  // with friction (block > 1)
  std::vector<char> factored_stick_;        // the stick set the factor holds
  SparseMatrix spring_change_;  // a direct solver's: the springs now less those in its factor
  Vector w_last_, w_before_;  // the last two answers (rotated): the extrapolated warm start
  Vector u_last_;             // the last answer as returned (is the caller continuing from it?)
  mutable double residual_left_ = 0;  // the last solve's equilibrium residual, at most (‖·‖₂; 0: solved exactly)
  Vector forces_last_, forces_before_;  // with friction: this rank's λ_ν then λ_τ of the last two answers
  /// coupling(): one entry of C, y[tangent] += coefficient × (K_rot x at the reaction row numbered `normal`
  /// among the coupled rows, if reaction; else x[normal]).
  struct Coupling {
    int tangent, normal;
    double coefficient;
    bool reaction;
  };
  mutable std::vector<Coupling> couplings_;
  mutable std::vector<char> coupled_;  // per local row: its μ λ_ν in the matrix (coupling())
  /// coupling(): a law_determines row's tangent dofs (−1 where none), its direction n and 1/μ (weigh()).
  struct LawRow {
    std::vector<int> dofs;
    Vector n;
    double inverse;
  };
  mutable std::vector<LawRow> law_rows_;
  mutable bool weighted_ = false;  // some rank has law rows (coupling())
  double force_scale_ = 0;             // the iteration's force scale (the direct solver's GMRES target)
  double newton_target_ = 0;           // the next coupled correction's residual (of the force scale), at least
  bool couple_ = true;                 // Coulomb's bound in Newton's step (else lagged one iterate)
  mutable bool coupled_failed_ = false;  // the last coupled solve's GMRES failed (the iteration stops)
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
