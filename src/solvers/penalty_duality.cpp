#include "solvers/penalty_duality.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace vpc {

PenaltyDuality::PenaltyDuality(const SparseMatrix& H, SparseMatrix E, double omega)
    : E_(std::move(E)), Et_(E_.transpose()), omega_(omega), factor_(make_cholmod_solver()) {
  require(omega > 0, "penalty-duality: omega must be > 0 (got {})", omega);
  const SparseMatrix Hp = H + omega * SparseMatrix(Et_ * E_);
  factor_->factorize(Hp, "penalty-duality matrix H + omega E^T E");
}

PenaltyDualityResult PenaltyDuality::solve(const Vector& b, const Vector& lo, const Vector& hi, Vector& x,
                                           Vector& theta, double tolerance, int max_iterations) {
  const int m = static_cast<int>(E_.rows());
  if (q_.size() != m) q_ = Vector::Zero(m);
  const double w = omega_;
  PenaltyDualityResult res;
  Vector x_old = x.size() == b.size() ? x : Vector::Zero(b.size());
  double bound_scale = 0;
  for (int i = 0; i < m; ++i) {
    if (std::isfinite(lo[i])) bound_scale = std::max(bound_scale, std::abs(lo[i]));
    if (std::isfinite(hi[i])) bound_scale = std::max(bound_scale, std::abs(hi[i]));
  }
  Vector q_used = q_;
  for (res.iterations = 1; res.iterations <= max_iterations; ++res.iterations) {
    q_used = q_;
    x = factor_->solve(Vector(b - Et_ * q_));
    const Vector y = E_ * x;
    double violation = 0;
    for (int i = 0; i < m; ++i) {
      const double p = std::clamp(2 * y[i] + q_[i] / w, lo[i], hi[i]);
      q_[i] = 2 * w * y[i] + q_[i] - 2 * w * p;
      violation = std::max({violation, y[i] - hi[i], lo[i] - y[i]});
    }
    const double scale = std::max({x.cwiseAbs().maxCoeff(), bound_scale, 1e-300});
    const double step = (x - x_old).cwiseAbs().maxCoeff();
    x_old = x;
    if (res.iterations > 1 && step <= tolerance * scale && violation <= tolerance * scale) {
      res.converged = true;
      break;
    }
  }
  res.iterations = std::min(res.iterations, max_iterations);
  theta = q_used + w * (E_ * x);  // the q that produced x: H x + Eᵀθ = b exactly
  return res;
}

}  // namespace vpc
