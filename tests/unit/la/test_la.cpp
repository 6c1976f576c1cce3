// The linear-algebra layer (la/) on one process: the communicator's collectives
// are identities, a layout without ghosts, the Eigen operator's mult, diagonal
// and restriction against dense references, the CHOLMOD factor and its halves,
// and the box QP over a factor without halves (the path the PETSc backend takes).
#include "core/error.hpp"
#include "la/comm.hpp"
#include "la/linear_solver.hpp"
#include "la/vector.hpp"
#include "solvers/box_qp.hpp"

#include <gtest/gtest.h>

#include <random>

namespace vpc::la {
namespace {

Eigen::SparseMatrix<double> tridiagonal(int n, double diag, double off) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, diag);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, off);
      t.emplace_back(i + 1, i, off);
    }
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(LaComm, OneProcessCollectivesAreIdentities) {
  const Comm c;
  EXPECT_TRUE(c.serial());
  EXPECT_EQ(c.rank(), 0);
  EXPECT_EQ(c.size(), 1);
  EXPECT_EQ(c.sum(2.5), 2.5);
  EXPECT_EQ(c.sum(7LL), 7LL);
  EXPECT_EQ(c.max(-1.0), -1.0);
  EXPECT_EQ(c.min(3.0), 3.0);
  EXPECT_TRUE(c.all(true));
  EXPECT_FALSE(c.all(false));
  EXPECT_FALSE(c.any(false));
  double v[2] = {1, 2};
  c.sum(v, 2);
  EXPECT_EQ(v[1], 2.0);
  EXPECT_NO_THROW(c.throw_if_any(false, "no"));
  try {
    c.throw_if_any(true, "rank 0: bad value at node 3");
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "rank 0: bad value at node 3");
  }
}

TEST(LaLayout, OneProcessHasNoGhostsAndGathersInPlace) {
  auto layout = std::make_shared<const Layout>(4);
  EXPECT_EQ(layout->n_owned(), 4);
  EXPECT_EQ(layout->n_ghosts(), 0);
  EXPECT_EQ(layout->n_global(), 4);
  Vector v(layout);
  v.local() << 1, 2, 3, 4;
  v.update_ghosts();
  v.add_ghosts_to_owners();
  EXPECT_EQ(v.local(), Eigen::Vector4d(1, 2, 3, 4));
  const Eigen::VectorXd g = layout->gather(v.local());
  EXPECT_EQ(g, v.local());
  Eigen::VectorXd back;
  layout->scatter(g, back);
  EXPECT_EQ(back, v.local());
}

TEST(LaBlockSplit, PetscsSplitAndAllOnTheFirst) {
  const BlockSplit s(10, 4);  // 3, 3, 2, 2
  EXPECT_EQ(s.n_blocks(), 4);
  EXPECT_EQ(s.n(), 10);
  EXPECT_EQ(s.begin(0), 0);
  EXPECT_EQ(s.end(0), 3);
  EXPECT_EQ(s.begin(2), 6);
  EXPECT_EQ(s.size(3), 2);
  for (long long i = 0; i < 10; ++i) EXPECT_LE(s.begin(s.block_of(i)), i);
  EXPECT_EQ(s.block_of(2), 0);
  EXPECT_EQ(s.block_of(3), 1);
  EXPECT_EQ(s.block_of(9), 3);
  const BlockSplit few(2, 3);  // more blocks than entries: the last is empty
  EXPECT_EQ(few.size(0) + few.size(1), 2);
  EXPECT_EQ(few.size(2), 0);
  const BlockSplit root = BlockSplit::first_only(7, 3);
  EXPECT_EQ(root.size(0), 7);
  EXPECT_EQ(root.size(1), 0);
  EXPECT_EQ(root.block_of(6), 0);
}

TEST(LaLayout, OneProcessBlocksAreItsEntries) {
  const Layout layout(3);
  const Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(6, 1, 6);  // 2 values per entry
  const Eigen::VectorXd block = layout.to_blocks(v, BlockSplit(3, 1), 2);
  EXPECT_EQ(block, v);
  Eigen::VectorXd back;
  layout.from_blocks(block, BlockSplit(3, 1), back, 2);
  EXPECT_EQ(back, v);
}

TEST(LaOperator, MultDiagonalAndRestrictionMatchDense) {
  const SparseOperator A(tridiagonal(6, 4.0, -1.0));
  const Eigen::MatrixXd D = Eigen::MatrixXd(A.matrix());
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(6, 1.0, 2.0);
  Eigen::VectorXd y, r;
  A.mult(x, y);
  EXPECT_LE((y - D * x).norm(), 1e-14);
  A.residual(x, x, r);
  EXPECT_LE((r - (x - D * x)).norm(), 1e-14);
  EXPECT_EQ(A.diagonal(), D.diagonal());
  const std::vector<char> fixed = {1, 0, 0, 1, 0, 1};
  const auto AFF = A.restrict_to_free(fixed);
  ASSERT_EQ(AFF->n_owned(), 3);
  const std::vector<int> F = {1, 2, 4};
  Eigen::MatrixXd DFF(3, 3);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) DFF(a, b) = D(F[a], F[b]);
  EXPECT_EQ(Eigen::MatrixXd(dynamic_cast<const SparseOperator&>(*AFF).matrix()), DFF);
}

TEST(LaOperator, FixedRowsKeepTheirDiagonalAndThePattern) {
  const SparseOperator A(tridiagonal(6, 4.0, -1.0));
  const Eigen::MatrixXd D = Eigen::MatrixXd(A.matrix());
  const std::vector<char> fixed = {0, 1, 0, 0, 1, 0};
  const auto B = A.with_fixed(fixed);
  const Eigen::MatrixXd DB = Eigen::MatrixXd(dynamic_cast<const SparseOperator&>(*B).matrix());
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const double expected = fixed[i] || fixed[j] ? (i == j ? D(i, i) : 0.0) : D(i, j);
      EXPECT_EQ(DB(i, j), expected) << i << "," << j;
    }
  EXPECT_EQ(B->nonzeros(), A.nonzeros());  // explicit zeros: a factor reuses its analysis
}

TEST(LaOperator, RowProductIsThoseRowsOfTheProduct) {
  // Symmetric with three bands, so a row reads several columns on both sides.
  Eigen::SparseMatrix<double> M = tridiagonal(9, 5.0, -1.0);
  for (int i = 0; i + 3 < 9; ++i) M.coeffRef(i, i + 3) = M.coeffRef(i + 3, i) = -0.5 - 0.1 * i;
  const SparseOperator A(M);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(9, -2.0, 3.0);
  Eigen::VectorXd Ax, y;
  A.mult(x, Ax);
  const std::vector<int> rows = {0, 3, 4, 8};
  A.rows(rows)(x, y);
  ASSERT_EQ(y.size(), 4);
  for (size_t k = 0; k < rows.size(); ++k) EXPECT_NEAR(y[k], Ax[rows[k]], 1e-14) << rows[k];
  A.rows({})(x, y);
  EXPECT_EQ(y.size(), 0);
}

TEST(LaFactor, CholmodSolvesAndItsHalvesComposeToTheSolve) {
  const SparseOperator A(tridiagonal(8, 3.0, -1.0));
  auto f = make_cholmod_factor();
  f->factorize(A, "test matrix");
  ASSERT_TRUE(f->has_halves());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(8, -1.0, 1.0);
  Eigen::VectorXd x;
  f->solve(b, x);
  Eigen::VectorXd Ax;
  A.mult(x, Ax);
  EXPECT_LE((Ax - b).norm(), 1e-13);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(8, 3);
  const Eigen::MatrixXd X = f->solve(B);
  EXPECT_LE((f->backward(f->forward(B)) - X).norm(), 1e-13);
  EXPECT_EQ(f->n_factorizations(), 1);
}

// GMRES on A + C with A's factor as preconditioner (solve_perturbed): C a nonsymmetric change
// of some rows (row i takes 0.3 × row i + 1 of A, as Coulomb's coupling takes a multiple of K's
// normal row), against a dense LU of A + C. A GMRES that cannot reach its tolerance is an error.
TEST(LaFactor, GmresSolvesTheFactoredMatrixWithANonsymmetricChange) {
  const Eigen::SparseMatrix<double> M = tridiagonal(12, 3.0, -1.0);
  const SparseOperator A(M);
  auto f = make_cholmod_factor();
  f->factorize(A, "test matrix");
  const std::vector<int> rows = {2, 5, 9};
  const Perturbation C = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
    y = Eigen::VectorXd::Zero(x.size());
    const Eigen::VectorXd Ax = M * x;
    for (const int i : rows) y[i] = 0.3 * Ax[i + 1];
  };
  Eigen::MatrixXd J = Eigen::MatrixXd(M);
  for (const int i : rows) J.row(i) += 0.3 * Eigen::MatrixXd(M).row(i + 1);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(12, -1.0, 2.0);
  Eigen::VectorXd x;
  f->solve_perturbed(A, C, b, x, 1e-12, "test matrix");
  EXPECT_LE((x - J.partialPivLu().solve(b)).norm(), 1e-10 * b.norm());
  EXPECT_LE((J * x - b).norm(), 1e-10 * b.norm());
  // A C that GMRES cannot follow in its iterations: x ↦ −A x makes A + C zero.
  const Perturbation annihilate = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) { y = -(M * v); };
  EXPECT_THROW(f->solve_perturbed(A, annihilate, b, x, 1e-12, "test matrix"), Error);
}

/// CHOLMOD without its halves: stands for MUMPS or CG in a serial test.
class NoHalves final : public LinearSolver {
 public:
  void factorize(const SpdOperator& A, const char* what) override { f_->factorize(A, what); }
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const override { f_->solve(b, x); }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const override { return f_->solve(B); }
  int n_factorizations() const override { return f_->n_factorizations(); }

 private:
  std::unique_ptr<LinearSolver> f_ = make_cholmod_factor();
};

TEST(LaBoxQp, WithoutHalvesTheReducedFactorGivesTheCapacitanceSolution) {
  const int n = 40;
  const Eigen::SparseMatrix<double> H = tridiagonal(n, 2.5, -1.0);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = 3.0 * std::sin(0.4 * i);  // both bounds active
  const Eigen::VectorXd lo = Eigen::VectorXd::Zero(n), hi = Eigen::VectorXd::Ones(n);
  SparseBoxQpOperator with(H, ReducedSolve::capacitance);
  Eigen::VectorXd x1 = Eigen::VectorXd::Zero(n);
  const BoxQpResult r1 = solve_box_qp(with, b, lo, hi, x1);
  const LinearSolverFactory no_halves = [](const std::string&) { return std::make_unique<NoHalves>(); };
  SparseBoxQpOperator without(std::make_unique<SparseOperator>(H), no_halves);
  Eigen::VectorXd x2 = Eigen::VectorXd::Zero(n);
  const BoxQpResult r2 = solve_box_qp(without, b, lo, hi, x2);
  ASSERT_TRUE(r1.converged && r2.converged);
  EXPECT_GT(r1.n_lower, 0);
  EXPECT_GT(r1.n_upper, 0);
  EXPECT_EQ(r1.n_lower, r2.n_lower);
  EXPECT_EQ(r1.n_upper, r2.n_upper);
  EXPECT_LE((x1 - x2).lpNorm<Eigen::Infinity>(), 1e-13);
  EXPECT_GT(with.n_capacitance_solves(), 0);
  EXPECT_EQ(without.n_capacitance_solves(), 0);
  EXPECT_GT(without.n_reduced_factor_solves(), 0);
}

TEST(LaBoxQp, CapacitanceAskedOfAFactorWithoutHalvesIsAnError) {
  const LinearSolverFactory no_halves = [](const std::string&) { return std::make_unique<NoHalves>(); };
  try {
    SparseBoxQpOperator op(std::make_unique<SparseOperator>(tridiagonal(4, 2.0, -1.0)), no_halves,
                           ReducedSolve::capacitance);
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("capacitance"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vpc::la
