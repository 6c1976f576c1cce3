#include "la/operator.hpp"

namespace vpc::la {

std::unique_ptr<SpdOperator> SparseOperator::restrict_to_free(const std::vector<char>& fixed) const {
  const int n = n_owned();
  std::vector<int> pos(n, -1);
  int n_free = 0;
  for (int i = 0; i < n; ++i)
    if (!fixed[i]) pos[i] = n_free++;
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < A_.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A_, k); it; ++it)
      if (pos[it.row()] >= 0 && pos[it.col()] >= 0) t.emplace_back(pos[it.row()], pos[it.col()], it.value());
  Eigen::SparseMatrix<double> AFF(n_free, n_free);
  AFF.setFromTriplets(t.begin(), t.end());
  return std::make_unique<SparseOperator>(std::move(AFF));
}

std::unique_ptr<SpdOperator> SparseOperator::with_fixed(const std::vector<char>& fixed) const {
  Eigen::SparseMatrix<double> B = A_;  // explicit zeros kept: the pattern stays A's
  for (int k = 0; k < B.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(B, k); it; ++it)
      if (fixed[it.row()] || fixed[it.col()]) if (it.row() != it.col()) it.valueRef() = 0.0;
  return std::make_unique<SparseOperator>(std::move(B));
}

RowProduct SparseOperator::rows(const std::vector<int>& rows) const {
  // A is symmetric and stored whole: row i is column i, contiguous in Eigen's column-major storage.
  std::vector<Eigen::Triplet<double>> entries;
  for (size_t k = 0; k < rows.size(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A_, rows[k]); it; ++it)
      entries.emplace_back(static_cast<int>(k), static_cast<int>(it.row()), it.value());
  Eigen::SparseMatrix<double, Eigen::RowMajor> R(static_cast<Eigen::Index>(rows.size()), A_.cols());
  R.setFromTriplets(entries.begin(), entries.end());
  return [R = std::move(R)](const Eigen::VectorXd& x, Eigen::VectorXd& y) { y = R * x; };
}

}  // namespace vpc::la
