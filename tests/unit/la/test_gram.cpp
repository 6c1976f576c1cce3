// la/gram.hpp: YᵀY of a sparse matrix with both kinds of rows (few entries, and entries in most
// columns: the rank updates' chunks), against the dense product.
#include "la/gram.hpp"

#include <gtest/gtest.h>

#include <random>

namespace vpc {
namespace {

SparseMatrix random_rows(int rows, int cols, int dense_rows, std::mt19937& rng) {
  std::uniform_real_distribution<double> value(-1, 1);
  std::uniform_int_distribution<int> column(0, cols - 1);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < rows; ++i) {
    if (i % (rows / dense_rows) == 0) {
      for (int j = 0; j < cols; ++j)
        if (j % 3 != 0) t.emplace_back(i, j, value(rng));  // 2/3 of the columns: a dense row
    } else {
      for (int k = 0; k < 3; ++k) t.emplace_back(i, column(rng), value(rng));  // summed where repeated
    }
  }
  SparseMatrix Y(rows, cols);
  Y.setFromTriplets(t.begin(), t.end());
  return Y;
}

TEST(Gram, EqualsTheDenseProductWithSparseAndDenseRows) {
  std::mt19937 rng(7);
  // 700 dense rows of 300 columns: two full chunks of 256 and a partial one.
  for (const auto& [rows, cols, dense] : {std::tuple{2000, 300, 700}, std::tuple{50, 40, 5}, std::tuple{30, 1, 1}}) {
    const SparseMatrix Y = random_rows(rows, cols, dense, rng);
    const Eigen::MatrixXd expected = Eigen::MatrixXd(Y).transpose() * Eigen::MatrixXd(Y);
    const Eigen::MatrixXd S = gram(Y);
    ASSERT_EQ(S.rows(), cols);
    EXPECT_LE((S - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff()) << rows << " x " << cols;
    EXPECT_EQ(S, S.transpose());
  }
}

TEST(Gram, OfAnEmptyMatrixIsZero) {
  EXPECT_EQ(gram(SparseMatrix(10, 4)), Eigen::MatrixXd::Zero(4, 4));
  EXPECT_EQ(gram(SparseMatrix(0, 0)).size(), 0);
}

}  // namespace
}  // namespace vpc
