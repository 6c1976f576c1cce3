#include "solvers/pull_off.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <limits>

namespace vpc {

Eigen::VectorXd nonnegative_least_squares(const Eigen::MatrixXd& B, const Eigen::VectorXd& t) {
  const Eigen::Index n = B.cols();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<char> passive(static_cast<std::size_t>(n), 0);
  const double scale = std::max(B.norm() * t.norm(), std::numeric_limits<double>::min());
  const double tol = 1e-13 * scale;
  // Solves for the passive columns alone (least squares, the minimum-norm solution where they are
  // dependent: B has k ≤ 6 rows and several bonded nodes push along one motion).
  auto solve_passive = [&](Eigen::VectorXd& z) {
    std::vector<Eigen::Index> cols;
    for (Eigen::Index j = 0; j < n; ++j)
      if (passive[static_cast<std::size_t>(j)]) cols.push_back(j);
    Eigen::MatrixXd Bp(B.rows(), static_cast<Eigen::Index>(cols.size()));
    for (std::size_t q = 0; q < cols.size(); ++q) Bp.col(static_cast<Eigen::Index>(q)) = B.col(cols[q]);
    const Eigen::VectorXd zp = Bp.completeOrthogonalDecomposition().solve(t);
    z = Eigen::VectorXd::Zero(n);
    for (std::size_t q = 0; q < cols.size(); ++q) z[cols[q]] = zp[static_cast<Eigen::Index>(q)];
  };
  for (Eigen::Index outer = 0; outer < 3 * n + 10; ++outer) {
    const Eigen::VectorXd w = B.transpose() * (t - B * x);
    Eigen::Index best = -1;
    double most = tol;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!passive[static_cast<std::size_t>(j)] && w[j] > most) most = w[j], best = j;
    if (best < 0) break;  // KKT: every active column's gradient ≤ 0
    passive[static_cast<std::size_t>(best)] = 1;
    for (Eigen::Index inner = 0; inner <= n; ++inner) {
      Eigen::VectorXd z;
      solve_passive(z);
      bool positive = true;
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[static_cast<std::size_t>(j)] && z[j] <= 0) positive = false;
      if (positive) {
        x = z;
        break;
      }
      double step = 1;  // back along x → z to the first passive entry that reaches 0
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[static_cast<std::size_t>(j)] && z[j] <= 0) step = std::min(step, x[j] / (x[j] - z[j]));
      x += step * (z - x);
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[static_cast<std::size_t>(j)] && x[j] <= 1e-15 * x.cwiseAbs().maxCoeff()) passive[static_cast<std::size_t>(j)] = 0, x[j] = 0;
    }
  }
  return x;
}

double unbalanced_share(const la::Comm& comm, const ContactConstraints& c, const Vector& F) {
  const Eigen::MatrixXd& R = c.free_motions;
  const auto k = R.cols();
  if (k == 0) return 0;
  // Every row's Rᵀ N_iᵀ and lower bound, on every rank (m × (k + 1), this rank's rows filled, summed).
  Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(c.m, k + 1);
  const Eigen::MatrixXd NR = c.N * R;  // local rows × k
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    rows.row(c.rows[i]).head(k) = NR.row(static_cast<Eigen::Index>(i));
    rows(c.rows[i], k) = c.lower_of(static_cast<Eigen::Index>(i));
  }
  comm.sum(rows.data(), static_cast<int>(rows.size()));
  Eigen::VectorXd f = R.transpose() * F;
  comm.sum(f.data(), static_cast<int>(k));
  const Eigen::MatrixXd B = rows.leftCols(k).transpose();
  const Eigen::VectorXd pulled = B * rows.col(k);  // the rows at their lower bounds
  const Eigen::VectorXd t = f - pulled;
  const double scale = std::max({f.norm(), pulled.norm(), std::numeric_limits<double>::min()});
  if (t.norm() <= kPullOffShare * scale) return 0;
  const Eigen::VectorXd mu = nonnegative_least_squares(B, t);
  return (B * mu - t).norm() / scale;
}

}  // namespace vpc
