#include "solvers/penalty_duality.hpp"

#include "core/error.hpp"
#include "la/backend.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

PenaltyDuality::PenaltyDuality(const la::SpdOperator& H, SparseMatrix E, double omega,
                               const la::LinearSolverFactory& make_factor, const std::string& name)
    : E_(std::move(E)), Et_(E_.transpose()), omega_(omega), comm_(H.comm()) {
  require(omega > 0, "penalty-duality: omega must be > 0 (got {})", omega);
  Hp_ = H.plus(omega * SparseMatrix(Et_ * E_));
  factor_ = make_factor(name);
  factor_->factorize(*Hp_, "penalty-duality matrix H + omega E^T E");
}

PenaltyDuality::PenaltyDuality(const SparseMatrix& H, SparseMatrix E, double omega)
    : PenaltyDuality(la::SparseOperator(H), std::move(E), omega, la::factor_factory(la::serial_backend()), "H_pd") {}

PenaltyDualityResult PenaltyDuality::solve(const Vector& b, const Vector& lo, const Vector& hi, Vector& x,
                                           Vector& theta, double tolerance, int max_iterations,
                                           const std::function<bool(const Vector&)>& accept) {
  const int m = static_cast<int>(E_.rows());
  if (q_.size() != m) q_ = Vector::Zero(m);
  PenaltyDualityResult res;
  if (!comm_.all(b.allFinite())) {  // NaN or Inf data: no iteration could converge
    x = Vector::Constant(b.size(), std::numeric_limits<double>::quiet_NaN());
    theta = Vector::Constant(m, std::numeric_limits<double>::quiet_NaN());
    return res;
  }
  const double w = omega_;
  double bound_scale = 0;
  for (int i = 0; i < m; ++i) {
    if (std::isfinite(lo[i])) bound_scale = std::max(bound_scale, std::abs(lo[i]));
    if (std::isfinite(hi[i])) bound_scale = std::max(bound_scale, std::abs(hi[i]));
  }
  bound_scale = comm_.max(bound_scale);
  const auto inf = [&](const Vector& v) { return comm_.max(v.size() ? v.cwiseAbs().maxCoeff() : 0.0); };
  const double b_scale = inf(b);
  if (x.size() != b.size()) x = Vector::Zero(b.size());
  for (res.iterations = 1; res.iterations <= max_iterations; ++res.iterations) {
    factor_->solve(Vector(b - Et_ * q_), x);  // x: an iterative solver's initial guess
    const Vector y = E_ * x;
    // (x, θ) with θ = q + ωEx satisfies Hx + Eᵀθ = b exactly; stop when it also
    // satisfies the rest of KKT: lo ≤ Ex ≤ hi, θ ≥ 0 only at hi, θ ≤ 0 only at lo.
    theta = q_ + w * y;
    const double x_scale = std::max({inf(x), bound_scale, 1e-300});
    const double t_scale = std::max({inf(theta), b_scale, 1e-300});
    double kkt = 0;
    for (int i = 0; i < m; ++i) {
      kkt = std::max({kkt, (y[i] - hi[i]) / x_scale, (lo[i] - y[i]) / x_scale});
      // A multiplier of the wrong sign, or a non-zero one away from its bound, is an
      // error of size min(|θ_i|, distance to the bound): the natural (min) residual,
      // which unlike the product θ_i·distance does not vanish twice as fast.
      if (theta[i] > 0) kkt = std::max(kkt, std::min(theta[i] / t_scale, (hi[i] - y[i]) / x_scale));
      if (theta[i] < 0) kkt = std::max(kkt, std::min(-theta[i] / t_scale, (y[i] - lo[i]) / x_scale));
    }
    kkt = comm_.max(kkt);
    if (kkt <= tolerance || (accept && res.iterations % 8 == 0 && comm_.all(accept(x)))) {
      res.converged = true;
      break;
    }
    for (int i = 0; i < m; ++i) {
      const double p = std::clamp(2 * y[i] + q_[i] / w, lo[i], hi[i]);
      q_[i] = 2 * w * y[i] + q_[i] - 2 * w * p;
    }
  }
  res.iterations = std::min(res.iterations, max_iterations);
  return res;
}

}  // namespace vpc
