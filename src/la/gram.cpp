#include "la/gram.hpp"

#include "la/blas.hpp"

#include <algorithm>

namespace vpc {

Eigen::MatrixXd gram(const SparseMatrix& Y) {
  const Eigen::Index m = Y.cols();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> R = Y;
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(m, m);
  // Dense rows in chunks of at most 16 MiB (256 rows where m ≤ 8192).
  const Eigen::Index chunk = std::clamp<Eigen::Index>((Eigen::Index{16} << 20) / (8 * std::max<Eigen::Index>(m, 1)), 1, 256);
  Eigen::MatrixXd D;
  Eigen::Index filled = 0;
  auto flush = [&] {
    syrk_lower_add(D.data(), static_cast<int>(filled), static_cast<int>(chunk), static_cast<int>(m), S.data());
    filled = 0;
  };
  const auto* start = R.outerIndexPtr();
  for (Eigen::Index i = 0; i < R.rows(); ++i) {
    if (8 * (start[i + 1] - start[i]) > m) {
      if (filled == 0) D.setZero(chunk, m);
      for (auto k = start[i]; k < start[i + 1]; ++k) D(filled, R.innerIndexPtr()[k]) = R.valuePtr()[k];
      if (++filled == chunk) flush();
      continue;
    }
    for (auto a = start[i]; a < start[i + 1]; ++a)  // columns ascending: (a, b ≤ a) is in the lower triangle
      for (auto b = start[i]; b <= a; ++b) S(R.innerIndexPtr()[a], R.innerIndexPtr()[b]) += R.valuePtr()[a] * R.valuePtr()[b];
  }
  if (filled > 0) flush();
  for (Eigen::Index j = 1; j < m; ++j)
    for (Eigen::Index i = 0; i < j; ++i) S(i, j) = S(j, i);
  return S;
}

}  // namespace vpc
