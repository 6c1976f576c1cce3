#include "solvers/box_qp.hpp"

#include "core/error.hpp"
#include "la/backend.hpp"
#include "solvers/active_set_history.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

namespace {
constexpr double kRoundoff = 1e-14;

/// The monotone update that replaces the plain one once an active set has come back: every
/// bound the trial point crosses is taken, but of the bounds whose multiplier has the wrong
/// sign only the one with the largest violation (over every rank) is released (never one with
/// lo = hi, whose multiplier has either sign).
void monotone_update(const std::vector<signed char>& state, const Vector& r, const Vector& lo, const Vector& hi,
                     const la::Comm& comm, std::vector<signed char>& next) {
  double worst = 0;
  int at = -1;
  for (int i = 0; i < static_cast<int>(state.size()); ++i) {
    // The multiplier of a lower bound is −r_i, of an upper bound r_i: both ≥ 0 at a solution.
    const double violation = lo[i] == hi[i] ? 0.0 : state[i] == 1 ? r[i] : (state[i] == 2 ? -r[i] : 0.0);
    if (violation > worst) {
      worst = violation;
      at = i;
    }
  }
  const double global_worst = comm.max(worst);
  for (int i = 0; i < static_cast<int>(state.size()); ++i)
    if (state[i] == 1 || state[i] == 2) next[i] = i == at && worst == global_worst && worst > 0 ? 0 : state[i];
}
}  // namespace

DenseBoxQpOperator::DenseBoxQpOperator(Eigen::MatrixXd H) : H_(std::move(H)), diag_(H_.diagonal()) {}

void DenseBoxQpOperator::solve_free(const std::vector<char>& fixed, const Vector& b, Vector& x) {
  std::vector<int> F;
  for (int i = 0; i < size(); ++i)
    if (!fixed[i]) F.push_back(i);
  if (F.empty()) return;
  const int nf = static_cast<int>(F.size());
  Eigen::MatrixXd HFF(nf, nf);
  Vector r(nf);
  for (int a = 0; a < nf; ++a) {
    r[a] = b[F[a]];
    for (int j = 0; j < size(); ++j)
      if (fixed[j]) r[a] -= H_(F[a], j) * x[j];
    for (int c = 0; c < nf; ++c) HFF(a, c) = H_(F[a], F[c]);
  }
  const Vector xf = HFF.llt().solve(r);
  for (int a = 0; a < nf; ++a) x[F[a]] = xf[a];
}

const la::Comm& BoxQpOperator::comm() const {
  static const la::Comm one_process;
  return one_process;
}

SparseBoxQpOperator::SparseBoxQpOperator(std::unique_ptr<la::SpdOperator> H, const la::LinearSolverFactory& make_factor,
                                         ReducedSolve method, std::string what)
    : H_(std::move(H)), what_(std::move(what)), what_reduced_("reduced " + what_), diag_(H_->diagonal()),
      method_(method), full_(make_factor("H")), reduced_(make_factor("H_reduced")) {
  require(method_ != ReducedSolve::capacitance || full_->has_halves(),
          "damage: reduced = \"capacitance\" needs a factor with triangular halves (CHOLMOD); this linear solver "
          "has none (use \"automatic\" or \"reduced-factor\")");
  if (!full_->has_halves()) method_ = ReducedSolve::reduced_factor;
  // The automatic choice's costs from the factor's symbolic analysis, at 10⁹ flop/s (as the
  // dense a × a Cholesky's below), not from timings: measured times made the choice, and so
  // the last bits of β, differ from run to run (a resumed run, a solver made for another step).
  if (const auto e = full_->analyze(*H_, what_.c_str())) {
    seconds_factor_ = e->flops / 1e9;
    seconds_forward_ = 2 * e->entries / 1e9;
  }
  full_->factorize(*H_, what_.c_str());
}

SparseBoxQpOperator::SparseBoxQpOperator(SparseMatrix H, ReducedSolve method)
    : SparseBoxQpOperator(std::make_unique<la::SparseOperator>(std::move(H)), la::factor_factory(la::serial_backend()), method) {}

void SparseBoxQpOperator::solve_free(const std::vector<char>& fixed, const Vector& b, Vector& x) {
  std::vector<int> active;
  for (int i = 0; i < size(); ++i)
    if (fixed[i]) active.push_back(i);
  const la::Comm& comm = H_->comm();
  if (comm.all(active.empty())) {
    full_->solve(b, x);
  } else if (comm.all(static_cast<int>(active.size()) == size())) {
    return;  // nothing free
  } else if (use_capacitance(active)) {
    solve_capacitance(active, b, x);
  } else {
    solve_reduced_factor(fixed, b, x);
  }
}

bool SparseBoxQpOperator::use_capacitance(const std::vector<int>& active) {
  if (method_ == ReducedSolve::reduced_factor) return false;
  const double a = static_cast<double>(active.size());
  if (has_z_.empty()) {
    has_z_.assign(size(), 0);
    z_columns_.resize(size());
  }
  std::vector<int> missing;
  for (int i : active)
    if (!has_z_[i]) missing.push_back(i);
  if (method_ == ReducedSolve::automatic && active != capacitance_set_) {
    // Cost of this active set by capacitance: the new forward solves and a dense
    // Cholesky (a³/3 flops at a conservative 10⁹ flop/s), against a reduced factor.
    const double cost = static_cast<double>(missing.size()) * seconds_forward_ + a * a * a / 3e9;
    if (cost > 0.5 * seconds_factor_) return false;
  }
  // Forward solves for the indices not seen active before, a block at a time.
  const double budget = 0.5 * full_->factor_bytes();
  const auto block = static_cast<size_t>(rhs_block_columns(size()));
  for (size_t k0 = 0; k0 < missing.size(); k0 += block) {
    if (method_ == ReducedSolve::automatic && z_bytes_ > budget) return false;
    const int nb = static_cast<int>(std::min(block, missing.size() - k0));
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(size(), nb);
    for (int j = 0; j < nb; ++j) E(missing[k0 + j], j) = 1;
    const Eigen::MatrixXd Zb = full_->forward(E);
    for (int j = 0; j < nb; ++j) {
      Eigen::SparseVector<double>& z = z_columns_[missing[k0 + j]];
      z = Zb.col(j).sparseView(0.0, 0.0);  // exact zeros off the elimination-tree path
      z_bytes_ += 12.0 * static_cast<double>(z.nonZeros());
      has_z_[missing[k0 + j]] = 1;
    }
  }
  return method_ == ReducedSolve::capacitance || z_bytes_ <= budget;
}

void SparseBoxQpOperator::solve_capacitance(const std::vector<int>& active, const Vector& b, Vector& x) {
  const int a = static_cast<int>(active.size());
  if (active != capacitance_set_) {
    std::vector<Eigen::Triplet<double>> t;
    for (int j = 0; j < a; ++j)
      for (Eigen::SparseVector<double>::InnerIterator it(z_columns_[active[j]]); it; ++it)
        t.emplace_back(static_cast<int>(it.index()), j, it.value());
    Z_.resize(size(), a);
    Z_.setFromTriplets(t.begin(), t.end());
    C_.compute(Eigen::MatrixXd(SparseMatrix(Z_.transpose() * Z_)));
    require(C_.info() == Eigen::Success, "box QP: the capacitance matrix of {} active bounds is not positive definite",
            a);
    capacitance_set_ = active;
  }
  // H x + Eμ = b, Eᵀx = x_A: with y = L⁻¹Pb, μ = C⁻¹(Zᵀy − x_A), x = PᵀL⁻ᵀ(y − Zμ).
  Vector xa(a);
  for (int j = 0; j < a; ++j) xa[j] = x[active[j]];
  const Vector y = full_->forward(b);
  const Vector mu = C_.solve(Vector(Z_.transpose() * y - xa));
  x = full_->backward(Vector(y - Z_ * mu));
  for (int j = 0; j < a; ++j) x[active[j]] = xa[j];  // exactly, not to round-off
  ++n_capacitance_;
}

void SparseBoxQpOperator::solve_reduced_factor(const std::vector<char>& fixed, const Vector& b, Vector& x) {
  const int n = size();
  // r = b − H_{·A} x_A
  Vector xa = Vector::Zero(n);
  for (int i = 0; i < n; ++i)
    if (fixed[i]) xa[i] = x[i];
  Vector r;
  H_->residual(b, xa, r);
  if (H_->comm().any(fixed != reduced_mask_)) {
    // The active set changed: factor H_FF (only then; it is reused while A repeats).
    free_ids_.clear();
    for (int i = 0; i < n; ++i)
      if (!fixed[i]) free_ids_.push_back(i);
    HFF_ = H_->restrict_to_free(fixed);
    reduced_->factorize(*HFF_, what_reduced_.c_str());
    reduced_mask_ = fixed;
  }
  Vector rf(static_cast<Eigen::Index>(free_ids_.size())), xf(rf.size());
  for (size_t a = 0; a < free_ids_.size(); ++a) {
    rf[a] = r[free_ids_[a]];
    xf[a] = x[free_ids_[a]];  // an iterative solver's initial guess
  }
  reduced_->solve(rf, xf);
  for (size_t a = 0; a < free_ids_.size(); ++a) x[free_ids_[a]] = xf[a];
  ++n_reduced_factor_;
}

double box_qp_kkt_residual(const BoxQpOperator& H, const Vector& b, const Vector& lo, const Vector& hi,
                           const Vector& x) {
  return box_qp_kkt_residual(H.multiply(x), H.diagonal(), b, lo, hi, x, H.comm());
}

double box_qp_kkt_residual(const Vector& Hx, const Vector& d, const Vector& b, const Vector& lo,
                           const Vector& hi, const Vector& x, const la::Comm& comm) {
  const Vector r = b - Hx;
  // NaN compares false: without this, max(res, NaN) would report a NaN iterate as exact.
  if (!comm.all(r.allFinite() && x.allFinite())) return std::numeric_limits<double>::infinity();
  double res = 0, scale = x.size() > 0 ? x.cwiseAbs().maxCoeff() : 0.0;
  for (int i = 0; i < x.size(); ++i) {
    const double p = std::clamp(x[i] + r[i] / d[i], lo[i], hi[i]);
    res = std::max(res, std::abs(x[i] - p));
    scale = std::max(scale, std::abs(b[i] / d[i]));
  }
  res = comm.max(res);
  scale = comm.max(scale);
  return scale > 0 ? res / scale : res;
}

BoxQpResult solve_box_qp(BoxQpOperator& H, const Vector& b, const Vector& lo, const Vector& hi, Vector& x,
                         int max_iterations) {
  const int n = H.size();
  const la::Comm& comm = H.comm();
  BoxQpResult res;
  if (x.size() != n) x = Vector::Zero(n);
  if (!comm.all(b.allFinite())) {  // NaN or Inf data (e.g. a formula): report, never "solve"
    res.kkt_residual = std::numeric_limits<double>::infinity();
    return res;
  }
  for (int i = 0; i < n; ++i) {
    require(lo[i] <= hi[i], "box QP: lower bound exceeds upper bound at index {}", i);
    x[i] = std::clamp(x[i], lo[i], hi[i]);
  }
  const Vector& d = H.diagonal();
  // state: 0 free, 1 at lower bound, 2 at upper bound; -1 = not yet determined.
  std::vector<signed char> state(n, -1), next(n);
  std::vector<char> fixed(n);
  // The plain update can cycle where H is not an M-matrix (the contact dual's dense S, for
  // one): a set that comes back switches to monotone updates (monotone_update), which
  // cannot return to a set (tests/unit/solvers/test_primal_active_set.cpp).
  ActiveSetHistory history;
  bool monotone = false;
  for (res.iterations = 0; res.iterations < max_iterations; ++res.iterations) {
    const Vector r = b - H.multiply(x);  // −∇: the multiplier of a bound is −r_i
    for (int i = 0; i < n; ++i) {
      const double trial = x[i] + r[i] / d[i];
      next[i] = trial < lo[i] || lo[i] == hi[i] ? 1 : (trial > hi[i] ? 2 : 0);
    }
    // Converged when the active sets repeat, or when x already satisfies KKT to
    // round-off: at a degenerate bound (multiplier exactly 0) round-off could
    // otherwise flip an index between two equivalent sets forever.
    if (comm.all(next == state) || box_qp_kkt_residual(Vector(b - r), d, b, lo, hi, x, comm) <= kRoundoff) {
      res.converged = true;
      break;
    }
    if (monotone) {
      monotone_update(state, r, lo, hi, comm, next);
      if (comm.all(next == state)) {  // no bound to take and no multiplier of the wrong sign: KKT holds
        res.converged = true;
        break;
      }
    } else if (history.came_back(next, comm)) {
      monotone = true;
      ++res.cycles;
      monotone_update(state, r, lo, hi, comm, next);
    }
    state = next;
    for (int i = 0; i < n; ++i) {
      fixed[i] = state[i] != 0;
      if (state[i] == 1) x[i] = lo[i];
      if (state[i] == 2) x[i] = hi[i];
    }
    H.solve_free(fixed, b, x);
  }
  // Free components may sit a round-off outside the box; the bounds are exact.
  long long at_bounds[2] = {0, 0};
  for (int i = 0; i < n; ++i) {
    x[i] = std::clamp(x[i], lo[i], hi[i]);
    at_bounds[0] += x[i] == lo[i];
    at_bounds[1] += x[i] == hi[i];
  }
  comm.sum(at_bounds, 2);
  res.n_lower = static_cast<int>(at_bounds[0]);
  res.n_upper = static_cast<int>(at_bounds[1]);
  res.kkt_residual = box_qp_kkt_residual(H, b, lo, hi, x);
  return res;
}

}  // namespace vpc
