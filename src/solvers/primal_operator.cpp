#include "solvers/primal_operator.hpp"

#include "core/error.hpp"
#include "solvers/primal_tuning.hpp"
#include "solvers/solver_cost.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

using namespace primal_tuning;

namespace {

/// A factorization's time in solves with the factor, from its analysis (CHOLMOD's flops and
/// entries at this machine's rates, solver_cost.hpp); kFactorSolves where the backend has none.
double factor_cost_in_solves(const std::optional<FactorEstimate>& e) {
  if (!e || !(e->entries > 0)) return kFactorSolves;
  const SolverRates rates = measured_rates();
  return (e->flops / rates.factor_flops_per_second) / (e->entries * rates.solve_seconds_per_entry);
}

bool same(const std::vector<Eigen::Triplet<double>>& a, const std::vector<Eigen::Triplet<double>>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const auto& x, const auto& y) {
    return x.row() == y.row() && x.col() == y.col() && x.value() == y.value();
  });
}

}  // namespace

PrimalOperator::PrimalOperator(std::shared_ptr<const la::SpdOperator> K, std::shared_ptr<const la::SpdOperator> K_rot,
                               std::shared_ptr<la::LinearSolver> factor, ContactConstraints c)
    : K_(std::move(K)), K_rot_(K_rot ? std::move(K_rot) : K_), factor_(std::move(factor)), c_(std::move(c)),
      basis_(contact_basis(c_.N, c_.node_dofs, c_.master_mean)), rows_(basis_.rows) {
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(rows_.size()); ++i) {
    lower_.push_back(c_.lower_of(i));
    if (c_.laws.empty()) continue;
    const ContactLaw& law = c_.law_of(i);  // rigid or linear (contact_capabilities.hpp: the primal's row)
    // An active compliant row is the spring of the law's linearization (exact for a linear law).
    spring_.push_back(law.rigid() ? 0.0 : law.spring_compliance(c_.compliance_of(i)));
  }
  require(basis_.P.size() == 0 || K_rot_ != K_, "internal: the primal contact solver needs Pᵀ K P for rotated rows");
  // c_i of the update rule λ_i − lower_i + c_i (N_i u − g_i) > 0: K's stiffness at the row's dof, per unit of N_i u.
  diagonal_ = K_rot_->diagonal();
  const Vector& d = diagonal_;
  for (const RotatedRow& r : rows_) scale_.push_back(d[r.dof] / (r.alpha * r.alpha));
}

void PrimalOperator::set_bond(const StepBonds& bonds) {
  set_bond_data(c_, bonds);
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(rows_.size()); ++i)
    lower_[static_cast<std::size_t>(i)] = c_.lower_of(i);
}

/// The semismooth Newton's choice of branch of a bonded row's graph (λ ≥ 0 at d = 0, or the law's
/// pressing branch; λ = a d for −L < d ≤ 0; λ = −a L below): by the resolvent z = λ + c d of the
/// graph (c the update rule's scale) on a rigid row, where d is 0 on its closed branch and λ is the
/// reaction: z > 0 closed, −(a + c) L < z ≤ 0 on the spring, else pulled off at −a L; by d alone on a
/// compliant row, whose force is a function of d.
char PrimalOperator::bonded_state(Eigen::Index i, double lambda, double d) const {
  const auto k = static_cast<std::size_t>(i);
  const double a = c_.bond_of(i), L = c_.bond_length_of(i);
  if (compliant(i)) return d > 0 ? kOn : d > -L ? kBonded : kOff;
  const double z = lambda - (lower_[k] + a * L) + scale_[k] * d;  // λ above the law's own bound
  return z > 0 ? kOn : z > -(a + scale_[k]) * L ? kBonded : kOff;
}

char PrimalOperator::first_state(Eigen::Index i, double lambda, double gap) const {
  if (c_.bond_of(i) > 0) return bonded_state(i, lambda, -gap);
  return lambda > lower(i) || gap < 0 ? kOn : kOff;
}

PrimalOperator::Iterate PrimalOperator::iterate(const std::vector<char>& active, const Vector& b, Vector& w, bool tight,
                                                Vector& lambda_local, ContactReport& rep, TangentialPart& tangents) {
  Iterate x;
  rep.factorizations += factorize_for(active, tangents);
  Solved solved = solve_constrained(active, b, w, tight, tangents);
  if (solved.failed && changed_) {
    // GMRES short of its tolerance on a kept factor: the factor for these sets, and the solve again.
    excess_products_ = std::numeric_limits<double>::infinity();
    rep.factorizations += factorize_for(active, tangents);
    solved = solve_constrained(active, b, w, tight, tangents);
  }
  x.residual_left = solved.residual_left;
  x.failed = solved.failed;
  K_rot_->residual(b, w, x.r);
  normal_update(active, w, x.r, lambda_local, x.next, x.most_negative, x.worst, tangents);
  ++rep.iterations;
  return x;
}

/// Factorizes K_rot with `active`'s constraints (and the tangents' fixed dofs and springs) unless the
/// factor already holds them, or, on a direct solver whose tangents keep it, unless the factor still
/// serves as GMRES's preconditioner for the operator with them (keep_factor). Returns 1 if it did.
int PrimalOperator::factorize_for(const std::vector<char>& active, const TangentialPart& tangents) {
  const la::Comm& comm = K_->comm();
  std::vector<Eigen::Triplet<double>> springs;
  std::vector<char> fixed(static_cast<size_t>(K_->n_owned()), 0);
  tangents.constrain(fixed, springs);  // friction: the stick rows' dofs, Newton's springs across the slip directions
  for (size_t i = 0; i < rows_.size(); ++i) {
    if (!active[i]) continue;
    if (active[i] == kBonded)  // the bond's spring a_i
      springs.emplace_back(rows_[i].dof, rows_[i].dof,
                           rows_[i].alpha * rows_[i].alpha * c_.bond_of(static_cast<Eigen::Index>(i)));
    else if (compliant(static_cast<Eigen::Index>(i)))
      springs.emplace_back(rows_[i].dof, rows_[i].dof, rows_[i].alpha * rows_[i].alpha / spring_[i]);
    else
      fixed[rows_[i].dof] = 1;
  }
  changed_ = false;
  if (A_ && comm.all(fixed == factored_fixed_) && comm.all(same(springs, factored_springs_))) {
    fixed_ = std::move(fixed);
    return 0;
  }
  const bool with_springs = comm.any(!springs.empty());
  if (A_ && tangents.keeps_factor() && !factor_->iterative() && keep_factor()) {
    // A direct solver keeps its factor while it serves: the operator with the sets and springs now
    // (A now) is applied by products, its change since the factor joins GMRES's operator
    // (CoulombCoupling) and the factor is its preconditioner.
    springs_now_ = with_springs ? owned_matrix(springs) : SparseMatrix();
    fixed_ = std::move(fixed);
    changed_ = true;
    return 0;
  }
  factored_springs_ = springs;
  // With friction the springs' pattern is every contact row's tangent block (zeros where a row
  // does not slip), within K_rot's own (a node's dofs couple), so that A_ keeps K_rot's pattern
  // as the slip set changes.
  if (with_springs) tangents.spring_pattern(springs);
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
    if (A_) {
      factor_->refactorize(*next, what);
    } else {
      if (tangents.keeps_factor() && !factor_->iterative())
        factor_solves_ = factor_cost_in_solves(factor_->analyze(*next, what));
      factor_->factorize(*next, what);
    }
    A_ = std::move(next);
  }
  factored_fixed_ = fixed;
  fixed_ = std::move(fixed);
  springs_now_ = SparseMatrix();
  excess_products_ = 0;
  return 1;
}

bool PrimalOperator::keep_factor() const {
  return excess_products_ < factor_solves_;
}

void PrimalOperator::count_perturbed(int products, double reduction) {
  // What a fresh factor would have taken for that reduction, at most; the rest is the kept factor's.
  const double decades = std::max(1.0, -std::log10(std::max(reduction, 1e-300)));
  const double fresh = kFreshProductsPerDecade * decades + 1;
  if (changed_) excess_products_ += std::max(0.0, products - fresh);
}

void PrimalOperator::change(const Vector& x, Vector& y) const {
  // (A now − A) x: A now is (K_rot + springs now) with the fixed rows now reduced to their diagonal
  // (la::SpdOperator::with_fixed; no spring lies on a fixed row, so the diagonal is K_rot's).
  Vector free_x = x, Ax;
  for (Eigen::Index j = 0; j < x.size(); ++j)
    if (fixed_[static_cast<std::size_t>(j)]) free_x[j] = 0;
  K_rot_->mult(free_x, y);
  if (springs_now_.nonZeros() > 0) y += springs_now_ * free_x;
  for (Eigen::Index j = 0; j < x.size(); ++j)
    if (fixed_[static_cast<std::size_t>(j)]) y[j] = diagonal_[j] * x[j];
  A_->mult(x, Ax);
  y -= Ax;
}

SparseMatrix PrimalOperator::owned_matrix(const std::vector<Eigen::Triplet<double>>& entries) const {
  SparseMatrix D(K_->n_owned(), K_->n_owned());
  D.setFromTriplets(entries.begin(), entries.end());
  return D;
}

/// w = the solution of K_rot w = b with the active rows: w_k = g/α on Signorini rows
/// (the others moved to the right-hand side), springs on the compliance rows, an inactive row's
/// force at its lower bound where that is not 0 (the load −N_iᵀ lower_i); the tangents' (with friction
/// the stick and slip rows' conditions, PrimalFriction::load, and Coulomb's coupling, CoulombCoupling).
PrimalOperator::Solved PrimalOperator::solve_constrained(const std::vector<char>& active, const Vector& b, Vector& w,
                                                         bool tight, TangentialPart& tangents) {
  Vector fixed_values = Vector::Zero(b.size());
  Vector rhs = b;
  for (size_t i = 0; i < rows_.size(); ++i) {
    if (!active[i]) {
      if (lower_[i] != 0) rhs[rows_[i].dof] -= rows_[i].alpha * lower_[i];
      continue;
    }
    const auto e = static_cast<Eigen::Index>(i);
    if (active[i] == kBonded)  // λ = a (N u − g): the spring's load a g
      rhs[rows_[i].dof] += rows_[i].alpha * c_.gap[e] * c_.bond_of(e);
    else if (compliant(e))
      rhs[rows_[i].dof] += rows_[i].alpha * c_.gap[e] / spring_[i];
    else
      fixed_values[rows_[i].dof] = c_.gap[e] / rows_[i].alpha;
  }
  const la::Perturbation C = tangents.load(*this, active, b, rhs, fixed_values);
  Vector coupling;
  K_rot_->mult(fixed_values, coupling);
  rhs -= coupling;
  for (Eigen::Index j = 0; j < rhs.size(); ++j)
    if (fixed_[j]) {  // the fixed rows of A keep K_rot's diagonal (la::SpdOperator::with_fixed)
      w[j] = fixed_values[j];
      rhs[j] = diagonal_[j] * fixed_values[j];
    }
  tangents.weigh(rhs);
  if (const auto goal = tangents.correction(static_cast<bool>(C), tight, factor_->iterative())) {
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
    // is about that). A direct solver's GMRES (its iterations are solves with the factor) takes the
    // same target, uncoupled the tolerance; an iterative one reduces each correction's residual
    // by kLeastForcing to kForcing (inexact Newton; lagged: kForcing), or, finding the sets, stops
    // where a loose solve would (loose_tolerance, of ‖rhs‖).
    // (Without Coulomb's bound in the matrix, C is only a kept factor's change: the tolerance, as
    // the exact solve with a fresh factor would be.)
    const double target = goal->target;
    const double to_target = target / std::max(norm, std::numeric_limits<double>::min());
    double rtol = kForcing;
    if (!factor_->iterative()) {
      rtol = std::clamp(to_target, 1e-14, kForcing);
    } else if (!tight) {
      const double loose = loose_tolerance(rhs, w), rhs_norm = std::sqrt(K_->comm().sum(rhs.squaredNorm()));
      rtol = loose > 0 && norm > 0 ? std::min(kLooseReduction, loose * rhs_norm / norm) : kForcing;
    } else if (goal->follow) {
      rtol = std::clamp(to_target, kLeastForcing, kForcing);
    }
    if (!C) {
      factor_->set_relative_tolerance(rtol);
      factor_->solve(r, delta);
      w += delta;
      return {rtol * norm, false};  // ‖r − Aδ‖₂ ≤ rtol ‖r‖₂
    }
    if (!factor_->iterative() && norm <= target) return {norm, false};  // within the target already
    int products = 0;
    const la::Perturbation counted = [&](const Vector& x, Vector& y) { ++products, C(x, y); };
    try {
      factor_->solve_perturbed(*A_, counted, r, delta, rtol > 0 ? rtol : 1e-12, "elastic stiffness K with Coulomb's coupling");
      count_perturbed(products, rtol);
    } catch (const Error&) {  // GMRES short of its tolerance: w stays, the caller stops
      return {0.0, true};
    }
    w += delta;
    A_->residual(rhs, w, r);  // the true residual (Eigen's GMRES stops on the preconditioned one)
    C(w, Cw);
    return {std::sqrt(K_->comm().sum((r - Cw).squaredNorm())), false};
  }
  if (tight && factor_->iterative()) {
    // The tight solve for the correction, as FrictionalSolve::correction asks with friction: the fixed rows
    // (w = g/α at the active rows, K_rot's diagonal times it in rhs) can dominate ‖rhs‖, against which an
    // iterative solver's tolerance is relative, while ‖b − A w‖ is the free rows' equilibrium alone (0 on the
    // fixed rows: w holds their values). hertz-2d-adapt's graded mesh on CG + GAMG: equilibrium residual
    // 1.1e-8 above the tolerance 1e-8 solving for w, the solver's 1e-10 of ‖rhs‖ ≈ 1e3.
    Vector r, delta = Vector::Zero(w.size());
    A_->residual(rhs, w, r);
    factor_->set_relative_tolerance(0.0);
    factor_->solve(r, delta);
    w += delta;
    return {0.0, false};
  }
  factor_->set_relative_tolerance(tight ? 0.0 : loose_tolerance(rhs, w));
  factor_->solve(rhs, w);
  return {0.0, false};  // a direct solve (a loose one never ends the iteration: was_tight)
}

/// A loose solve stops at kLooseTolerance ‖rhs‖ or at kLooseReduction of its initial
/// residual, whichever is smaller: a solve must answer a set change even when the guess
/// already meets kLooseTolerance (else the set flips back and forth on an unchanged w).
double PrimalOperator::loose_tolerance(const Vector& rhs, const Vector& w) const {
  Vector r;
  A_->residual(rhs, w, r);
  double norms[2] = {r.squaredNorm(), rhs.squaredNorm()};
  K_->comm().sum(norms, 2);
  if (!(norms[1] > 0)) return 0.0;
  const double rtol = std::min(kLooseTolerance, kLooseReduction * std::sqrt(norms[0] / norms[1]));
  return rtol > kLooseFloor ? rtol : 0.0;  // that close to the answer, the solver's own tolerance
}

/// λ_ν of the iterate (reaction r = b − K_rot w at an active Signorini row, the spring's force
/// at a compliant one, the slip law's at a row where CoulombCoupling::law_determines, the lower
/// bound at an inactive one) and the next normal set by the update rule
/// λ_i − lower_i + c_i (N_i u − g_i) > 0; `worst`: the active Signorini row whose force is the most
/// below its lower bound (if below it).
void PrimalOperator::normal_update(const std::vector<char>& active, const Vector& w, const Vector& r,
                                   Vector& lambda_local, std::vector<char>& next, double& most_negative,
                                   Eigen::Index& worst, const TangentialPart& tangents) const {
  auto law_determines = [&](Eigen::Index i) { return tangents.law_determines(i, c_); };
  auto law_normal_force = [&](Eigen::Index i) { return tangents.law_normal_force(i, r, c_); };
  next.assign(active.size(), 0);
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(rows_.size()); ++i) {
    const RotatedRow& row = rows_[i];
    const double gap = gap_left(w, i);
    if (c_.bond_of(i) > 0) {  // adhesion: three branches (bonded_state)
      const char state = active[i];
      lambda_local[i] = state == kOff      ? lower_[static_cast<std::size_t>(i)]
                        : state == kBonded ? -gap * c_.bond_of(i)
                        : compliant(i)     ? -gap / spring_[static_cast<std::size_t>(i)]
                                           : r[row.dof] / row.alpha;
      next[i] = bonded_state(i, lambda_local[i], state == kOn && !compliant(i) ? 0.0 : -gap);
      continue;
    }
    if (compliant(i)) {  // λ = k (N u − g)₊: active where the row penetrates
      lambda_local[i] = !active[i]           ? 0.0
                        : law_determines(i) ? law_normal_force(i)
                                            : -gap / spring_[static_cast<std::size_t>(i)];
      next[i] = gap < 0;
    } else {
      const double lower = lower_[static_cast<std::size_t>(i)];
      lambda_local[i] = !active[i] ? lower : law_determines(i) ? law_normal_force(i) : r[row.dof] / row.alpha;
      const double above = lambda_local[i] - lower;
      next[i] = above - scale_[i] * gap > 0;
      if (active[i] && above < most_negative) {
        most_negative = above;
        worst = i;
      }
    }
  }
}

void PrimalOperator::release_one(const std::vector<char>& active, std::vector<char>& next, double most_negative,
                                 Eigen::Index worst) const {
  const double global_worst = K_->comm().min(most_negative);
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(rows_.size()); ++i)
    if (!compliant(i) && !(c_.bond_of(i) > 0))  // (a bond's spring branch cannot cycle)
      next[i] = active[i] ? !(i == worst && most_negative == global_worst) : next[i];
}

Vector PrimalWarmStart::start_point(const PrimalOperator& op, const Vector& F, const Vector& u) const {
  Vector w = op.to_basis(u.size() == F.size() ? u : Vector(Vector::Zero(F.size())));
  // (continuing is collective: called on every rank, also one that owns no dofs, where the
  // sizes would agree trivially.)
  const bool extrapolate = continuing(op.comm(), u) && w_before_.size() == w.size();
  if (extrapolate) w = 2 * w_last_ - w_before_;
  return w;
}

void PrimalWarmStart::keep_answer(const PrimalOperator& op, const Vector& w, Vector& u) {
  w_before_ = std::move(w_last_);
  w_last_ = w;
  u = op.unrotate(w);
  u_last_ = u;
}

}  // namespace vpc
