// la/blas.cpp hands one-column GEMM and TRSM to GEMV and TRSV: the same numbers
// (to round-off) as the definitions, for every transpose, a strided column,
// β ≠ 0 and α ≠ 1; everything else reaches the BLAS's own routine.
#include "la/blas.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

extern "C" {
void dgemm_(const char*, const char*, const int*, const int*, const int*, const double*, const double*, const int*,
            const double*, const int*, const double*, double*, const int*);
void dtrsm_(const char*, const char*, const char*, const char*, const int*, const int*, const double*, const double*,
            const int*, double*, const int*);
}

namespace vpc {
namespace {

using Eigen::MatrixXd;

TEST(Blas, OneColumnGemmIsTheProductForEveryTranspose) {
  const int m = 37, k = 23, ld = 50;
  const double alpha = -1.5, beta = 0.25;
  for (const char* ta : {"N", "T"})
    for (const char* tb : {"N", "T"}) {
      SCOPED_TRACE(std::string(ta) + tb);
      const bool at = *ta == 'T', bt = *tb == 'T';
      const MatrixXd A = MatrixXd::Random(ld, 60), B = MatrixXd::Random(ld, 60), C0 = MatrixXd::Random(ld, 1);
      // op(A) is m × k, op(B) is k × 1, both inside ld-row storage.
      const MatrixXd opA = at ? MatrixXd(A.topLeftCorner(k, m).transpose()) : MatrixXd(A.topLeftCorner(m, k));
      const MatrixXd opB = bt ? MatrixXd(B.topLeftCorner(1, k).transpose()) : MatrixXd(B.topLeftCorner(k, 1));
      const MatrixXd expected = alpha * opA * opB + beta * C0.topRows(m);
      MatrixXd C = C0;
      const int n = 1;
      const long long before = blas_one_column_calls();
      dgemm_(ta, tb, &m, &n, &k, &alpha, A.data(), &ld, B.data(), &ld, &beta, C.data(), &ld);
      EXPECT_EQ(blas_one_column_calls(), before + 1);
      EXPECT_LE((C.topRows(m) - expected).cwiseAbs().maxCoeff(), 1e-13);
      EXPECT_EQ(C.bottomRows(ld - m), C0.bottomRows(ld - m));
    }
}

TEST(Blas, SeveralColumnsGoToTheBlasGemm) {
  const int m = 8, n = 3, k = 5;
  const double alpha = 1, beta = 0;
  const MatrixXd A = MatrixXd::Random(m, k), B = MatrixXd::Random(k, n);
  MatrixXd C(m, n);
  const long long before = blas_one_column_calls();
  dgemm_("N", "N", &m, &n, &k, &alpha, A.data(), &m, B.data(), &k, &beta, C.data(), &m);
  EXPECT_EQ(blas_one_column_calls(), before);
  EXPECT_LE((C - A * B).cwiseAbs().maxCoeff(), 1e-13);
}

TEST(Blas, OneColumnTrsmSolvesForEveryTriangleAndTranspose) {
  const int m = 29, ld = 31, n = 1;
  const double alpha = 2.5;
  MatrixXd A = MatrixXd::Random(ld, m);
  A.diagonal().array() += 8;  // well conditioned
  const MatrixXd b = MatrixXd::Random(ld, 1);
  for (const char* uplo : {"L", "U"})
    for (const char* trans : {"N", "T"})
      for (const char* diag : {"N", "U"}) {
        SCOPED_TRACE(std::string(uplo) + trans + diag);
        MatrixXd T = A.topRows(m);
        if (*uplo == 'L') T = MatrixXd(T.triangularView<Eigen::Lower>());
        else T = MatrixXd(T.triangularView<Eigen::Upper>());
        if (*diag == 'U') T.diagonal().setOnes();
        const MatrixXd opT = *trans == 'T' ? MatrixXd(T.transpose()) : T;
        MatrixXd x = b;
        dtrsm_("L", uplo, trans, diag, &m, &n, &alpha, A.data(), &ld, x.data(), &ld);
        EXPECT_LE((opT * x.topRows(m) - alpha * b.topRows(m)).cwiseAbs().maxCoeff(), 1e-12);
        EXPECT_EQ(x.bottomRows(ld - m), b.bottomRows(ld - m));
      }
}

}  // namespace
}  // namespace vpc
