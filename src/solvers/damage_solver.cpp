#include "solvers/damage_solver.hpp"

#include "core/error.hpp"
#include "solvers/box_qp.hpp"
#include "solvers/penalty_duality.hpp"

#include <algorithm>

namespace vpc {

namespace {

class ActiveSetDamageSolver final : public DamageSolver {
 public:
  explicit ActiveSetDamageSolver(const SparseMatrix& H) : op_(H) {}
  DamageReport solve(const Vector& rhs, Vector& beta) override {
    const int n = op_.size();
    const BoxQpResult r = solve_box_qp(op_, rhs, Vector::Zero(n), Vector::Ones(n), beta);
    return {r.converged, r.iterations, r.n_lower, r.n_upper, r.kkt_residual};
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

class PenaltyDualityDamageSolver final : public DamageSolver {
 public:
  PenaltyDualityDamageSolver(const SparseMatrix& H, double tol, int maxit)
      : H_(H), pd_(H, identity(static_cast<int>(H.rows())), H.diagonal().mean()), tol_(tol), maxit_(maxit) {}
  DamageReport solve(const Vector& rhs, Vector& beta) override {
    const int n = static_cast<int>(rhs.size());
    Vector theta;
    const PenaltyDualityResult r = pd_.solve(rhs, Vector::Zero(n), Vector::Ones(n), beta, theta, tol_, maxit_);
    DamageReport rep{r.converged, r.iterations, 0, 0, 0};
    // The iterate meets the box only to O(tolerance), from either side: project,
    // as the scheme requires β ∈ K^h exactly, snapping values within the
    // tolerance of a bound onto it, and report the KKT residual after that.
    for (int i = 0; i < n; ++i) {
      beta[i] = std::clamp(beta[i], 0.0, 1.0);
      if (beta[i] < tol_) beta[i] = 0.0;
      if (beta[i] > 1.0 - tol_) beta[i] = 1.0;
      rep.n_lower += beta[i] == 0.0;
      rep.n_upper += beta[i] == 1.0;
    }
    rep.kkt_residual = box_qp_kkt_residual(H_ * beta, H_.diagonal(), rhs, Vector::Zero(n), Vector::Ones(n), beta);
    return rep;
  }
  std::string name() const override { return "penalty-duality"; }
  Vector warm_state() const override { return pd_.multiplier_state(); }
  void set_warm_state(const Vector& q) override { pd_.set_multiplier_state(q); }
  int n_factorizations() const override { return 1; }
  double factor_bytes() const override { return pd_.factor_bytes(); }

 private:
  SparseMatrix H_;
  PenaltyDuality pd_;
  double tol_;
  int maxit_;
};

}  // namespace

std::unique_ptr<DamageSolver> make_damage_solver(const std::string& name, const SparseMatrix& H, double tolerance,
                                                 int max_iterations) {
  if (name == "active-set") return std::make_unique<ActiveSetDamageSolver>(H);
  if (name == "penalty-duality") return std::make_unique<PenaltyDualityDamageSolver>(H, tolerance, max_iterations);
  fail("unknown damage solver '{}'; expected active-set or penalty-duality", name);
}

}  // namespace vpc
