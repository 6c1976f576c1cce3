#include "solvers/damage_solver.hpp"

#include "core/error.hpp"
#include "la/backend.hpp"
#include "solvers/box_qp.hpp"
#include "solvers/penalty_duality.hpp"
#include "solvers/solver_failure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

namespace {

const char* const kDamageMatrix = "damage matrix H = M + k kappa A";

/// max_i (H·1)_i / H_ii over every rank: H = M + kκA is definite only through the mass part M
/// (A·1 = 0, so H·1 = M·1 up to round-off): this is M's share of H's diagonal, or round-off
/// where kκA has swamped M.
double mass_share(const la::SpdOperator& H) {
  Vector row_sums;
  H.mult(Vector::Ones(H.n_owned()), row_sums);
  const Vector diag = H.diagonal();
  double share = 0;
  for (Eigen::Index i = 0; i < diag.size(); ++i) share = std::max(share, std::abs(row_sums[i]) / diag[i]);
  return H.comm().max(share);
}

/// Makes a damage solver, whose set-up factorizes H; if that fails, says the likely cause,
/// measured on H (issue 26: a singular H was blamed on a missing clamp, which concerns K), located
/// at κ (`kappa_at`) when it is κ.
template <typename Make>
std::unique_ptr<DamageSolver> with_cause(const la::SpdOperator& H, const std::string& kappa_at, Make&& make) {
  const double share = mass_share(H);  // before `make` takes H
  try {
    return make();
  } catch (const Error& e) {
    // M's share of H's diagonal is about h²/(kκ) (h the cell size); CHOLMOD refuses H from about
    // kκ/h² = 1e14 (measured: 10 × 10 cells, k = 0.5: κ = 1e12 runs, 1e13 fails). Another cause
    // (a share above 1e-10) is left to the factor's own message.
    if (!(share < 1e-10)) throw;
    fail("{}: {}. Likely cause: k kappa is too large for the cells: H is definite only through its mass part M "
         "(A 1 = 0), and M, {:.1e} of H's diagonal, is lost in round-off next to k kappa A (k kappa / h^2 must stay "
         "below about 1e14, k the time step, h the cell size). Check kappa and the unit of length: kappa "
         "is a length^2 per unit of time, so a mesh in a small unit (a body 1e-9 across, in metres) needs kappa "
         "scaled by the square of that unit, or another unit",
         kappa_at, e.what(), share);
  }
}

class ActiveSetDamageSolver final : public DamageSolver {
 public:
  ActiveSetDamageSolver(std::unique_ptr<la::SpdOperator> H, const la::LinearSolverFactory& make_factor, ReducedSolve reduced)
      : op_(std::move(H), make_factor, reduced, kDamageMatrix) {}
  DamageReport solve(const Vector& rhs, Vector& beta) override {
    Vector lo, hi;
    bounds(beta, lo, hi);
    const BoxQpResult r = solve_box_qp(op_, rhs, lo, hi, beta);
    DamageReport rep{r.converged, r.iterations, 0, 0, r.kkt_residual};
    count_bounds(beta, op_.comm(), rep);
    return rep;
  }
  std::string name() const override { return "active-set"; }
  int n_factorizations() const override { return op_.n_factorizations(); }
  double factor_bytes() const override { return op_.factor_bytes(); }

 private:
  SparseBoxQpOperator op_;
};

SparseMatrix identity(int n) {
  SparseMatrix I(n, n);
  I.setIdentity();
  return I;
}

/// The 2-norm of a vector of owned entries.
double norm(const la::Comm& comm, const Vector& v) { return std::sqrt(comm.sum(v.squaredNorm())); }

/// With E = I the iteration contracts like |ω − μ| / (ω + μ) over the eigenvalues
/// μ of H: ω = √(μ_min μ_max) balances the two ends (the mean diagonal, tried
/// first, made the iteration count grow like h⁻²). μ_max by power iteration (from
/// 1 + i / (n − 1) at global index i, the same start on any number of ranks);
/// μ_min ≥ the smallest eigenvalue of the mass part, estimated as half the
/// smallest diagonal entry (exact for the P1 mass matrix in 1D up to a factor).
double default_omega(const la::SpdOperator& H) {
  const la::Comm& comm = H.comm();
  const int n = H.n_owned();
  const std::vector<long long> sizes = comm.all_gather(n);
  long long first = 0, total = 0;
  for (int r = 0; r < comm.size(); ++r) {
    if (r < comm.rank()) first += sizes[r];
    total += sizes[r];
  }
  Vector v = Vector::Ones(n) + Vector(Vector::LinSpaced(total, 0.0, 1.0)).segment(first, n);
  double mu_max = 0;
  Vector w;
  for (int it = 0; it < 30; ++it) {
    H.mult(v, w);
    const double w_norm = norm(comm, w);
    mu_max = w_norm / norm(comm, v);
    v = w / w_norm;
  }
  const Vector diag = H.diagonal();
  const double mu_min =
      0.5 * comm.min(n > 0 ? diag.minCoeff() : std::numeric_limits<double>::infinity());
  return std::sqrt(std::max(mu_min, 1e-300) * std::max(mu_max, mu_min));
}

class PenaltyDualityDamageSolver final : public DamageSolver {
 public:
  PenaltyDualityDamageSolver(std::unique_ptr<la::SpdOperator> H, const la::LinearSolverFactory& make_factor, double tol,
                             int maxit)
      : H_(std::move(H)), diag_(H_->diagonal()),
        pd_(*H_, identity(H_->n_owned()), default_omega(*H_), make_factor, "H_pd"), tol_(tol), maxit_(maxit) {}
  DamageReport solve(const Vector& rhs, Vector& beta) override {
    const int n = static_cast<int>(rhs.size());
    const la::Comm& comm = H_->comm();
    Vector theta;
    // Converged also when the projection onto [0, 1] satisfies the KKT conditions
    // to the tolerance (the measure reported for both damage solvers): at a
    // degenerate bound (β = 1 with a zero multiplier, e.g. β0 = 1) the
    // multiplier test alone converges only linearly.
    Vector lo, hi;
    bounds(beta, lo, hi);
    auto accept = [&](const Vector& x) {
      const Vector p = x.cwiseMax(lo).cwiseMin(hi);
      return box_qp_kkt_residual(product(p), diag_, rhs, lo, hi, p, comm) <= tol_;
    };
    const PenaltyDualityResult r = pd_.solve(rhs, lo, hi, beta, theta, tol_, maxit_, accept);
    DamageReport rep{r.converged, r.iterations, 0, 0, 0};
    // The iterate meets the box only to O(tolerance), from either side: project,
    // as the scheme requires β ∈ K^h exactly, snapping values within the
    // tolerance of a bound onto it (a held node onto its value), and report the KKT residual after that.
    for (int i = 0; i < n; ++i) {
      beta[i] = std::clamp(beta[i], lo[i], hi[i]);
      if (lo[i] == hi[i]) continue;
      if (beta[i] < tol_) beta[i] = 0.0;
      if (beta[i] > 1.0 - tol_) beta[i] = 1.0;
    }
    count_bounds(beta, comm, rep);
    rep.kkt_residual = box_qp_kkt_residual(product(beta), diag_, rhs, lo, hi, beta, comm);
    return rep;
  }
  std::string name() const override { return "penalty-duality"; }
  Vector warm_state() const override { return pd_.multiplier_state(); }
  void set_warm_state(const Vector& q) override { pd_.set_multiplier_state(q); }
  int n_factorizations() const override { return 1; }
  double factor_bytes() const override { return pd_.factor_bytes(); }

 private:
  Vector product(const Vector& x) const {
    Vector y;
    H_->mult(x, y);
    return y;
  }
  std::unique_ptr<la::SpdOperator> H_;
  Vector diag_;
  PenaltyDuality pd_;
  double tol_;
  int maxit_;
};

}  // namespace

void DamageSolver::bounds(const Vector& beta, Vector& lo, Vector& hi) const {
  lo = Vector::Zero(beta.size());
  hi = Vector::Ones(beta.size());
  if (held_.empty()) return;
  require(static_cast<Eigen::Index>(held_.size()) == beta.size(), "internal: {} held flags for {} damage nodes",
          held_.size(), beta.size());
  for (Eigen::Index i = 0; i < beta.size(); ++i)
    if (held_[i]) lo[i] = hi[i] = beta[i];
}

void DamageSolver::count_bounds(const Vector& beta, const la::Comm& comm, DamageReport& r) {
  long long at_bounds[2] = {(beta.array() == 0.0).count(), (beta.array() == 1.0).count()};
  comm.sum(at_bounds, 2);
  r.n_lower = static_cast<int>(at_bounds[0]);
  r.n_upper = static_cast<int>(at_bounds[1]);
}

std::string damage_failure(const DamageReport& r, double tolerance) {
  if (std::isinf(r.kkt_residual) || std::isnan(r.kkt_residual)) return kSolverMetNonFinite;
  return solver_failure(
      r.converged, r.iterations,
      r.kkt_residual <= tolerance
          ? ""
          : fmt::format("KKT residual {:.2e} (stationarity, 0 <= beta <= 1 and complementarity) above the tolerance {:.1e}",
                        r.kkt_residual, tolerance));
}

std::unique_ptr<DamageSolver> make_damage_solver(const std::string& name, std::unique_ptr<la::SpdOperator> H,
                                                 const la::LinearSolverFactory& make_factor, ReducedSolve reduced,
                                                 const std::string& kappa_at, double tolerance, int max_iterations) {
  const la::SpdOperator& h = *H;
  if (name == "active-set")
    return with_cause(h, kappa_at,
                      [&] { return std::make_unique<ActiveSetDamageSolver>(std::move(H), make_factor, reduced); });
  if (name == "penalty-duality")
    return with_cause(h, kappa_at, [&] {
      return std::make_unique<PenaltyDualityDamageSolver>(std::move(H), make_factor, tolerance, max_iterations);
    });
  fail("unknown damage solver '{}'; expected active-set or penalty-duality", name);
}

std::unique_ptr<DamageSolver> make_damage_solver(const std::string& name, const SparseMatrix& H, double tolerance,
                                                 int max_iterations, ReducedSolve reduced) {
  return make_damage_solver(name, std::make_unique<la::SparseOperator>(H), la::factor_factory(la::serial_backend()), reduced,
                            "[damage] kappa", tolerance, max_iterations);
}

}  // namespace vpc
