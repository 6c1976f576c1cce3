#include "solvers/anderson_mixing.hpp"

#include <Eigen/Dense>

namespace vpc {

Vector AndersonMixing::next(const la::Comm& comm, const Vector& x, const Vector& g) {
  const Vector f = g - x;
  // A flag, not x_last_'s size: a rank without contact rows has empty vectors from the start, and
  // every rank must keep the same number of differences (the sums below are collective).
  if (have_last_) {
    dx_.push_back(x - x_last_);
    df_.push_back(f - f_last_);
    if (static_cast<int>(df_.size()) > depth_) {
      dx_.erase(dx_.begin());
      df_.erase(df_.begin());
    }
  }
  x_last_ = x;
  f_last_ = f;
  have_last_ = true;
  const auto m = static_cast<Eigen::Index>(df_.size());
  if (m == 0) return g;
  // γ = argmin ‖f − ΔF γ‖ by its normal equations (m ≤ depth numbers, the same on every rank).
  std::vector<double> sums(static_cast<std::size_t>(m * (m + 1)));
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) sums[static_cast<std::size_t>(a * m + b)] = df_[a].dot(df_[b]);
    sums[static_cast<std::size_t>(m * m + a)] = df_[a].dot(f);
  }
  comm.sum(sums.data(), static_cast<int>(sums.size()));
  Eigen::MatrixXd A(m, m);
  Vector rhs(m);
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) A(a, b) = sums[static_cast<std::size_t>(a * m + b)];
    rhs[a] = sums[static_cast<std::size_t>(m * m + a)];
  }
  const Vector gamma = A.completeOrthogonalDecomposition().solve(rhs);
  Vector out = g;
  for (Eigen::Index a = 0; a < m; ++a) out -= gamma[a] * (dx_[a] + df_[a]);
  return comm.all(out.allFinite()) ? out : g;
}

}  // namespace vpc
