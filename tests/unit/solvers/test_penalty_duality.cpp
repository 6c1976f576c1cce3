// Penalty–duality (Bermúdez–Moreno, solvers/penalty_duality): on the box QPs of
// test_box_qp it must reach the active-set solution, and its multiplier θ must be
// the Lagrange multiplier (signs, H x + Eᵀθ = b); warm start, limits and errors.
#include "solvers/penalty_duality.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "mesh/generators.hpp"
#include "solvers/box_qp.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace vpc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Interior (Dirichlet) block of the P1 Laplacian on (0, 1) with n cells.
SparseMatrix laplacian_1d(int n) {
  const Mesh m = make_interval(0, 1, n);
  const SparseMatrix A = assemble_laplacian(m, compute_geometry(m));
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < A.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(A, k); it; ++it)
      if (it.row() > 0 && it.row() < n && it.col() > 0 && it.col() < n)
        t.emplace_back(static_cast<int>(it.row()) - 1, static_cast<int>(it.col()) - 1, it.value());
  SparseMatrix S(n - 1, n - 1);
  S.setFromTriplets(t.begin(), t.end());
  return S;
}

SparseMatrix identity(int n) {
  SparseMatrix I(n, n);
  I.setIdentity();
  return I;
}

/// Exact load ∫ f ψ_i for f constant on each cell.
Vector cellwise_load(int n, const std::function<double(double)>& f) {
  const double h = 1.0 / n;
  Vector b(n - 1);
  for (int k = 0; k < n - 1; ++k) b[k] = 0.5 * h * (f((k + 0.5) * h) + f((k + 1.5) * h));
  return b;
}

struct Case {
  const char* name;
  int n;
  std::function<double(double)> f;
  double lo, hi;
};

// The three 1D obstacle problems of test_box_qp: lower only, upper only, [0, 1].
std::vector<Case> cases() {
  return {{"lower obstacle", 40, [](double) { return -8.0; }, -0.25, kInf},
          {"upper obstacle", 40, [](double) { return 8.0; }, -kInf, 0.25},
          {"two-sided [0,1]", 64, [](double x) { return std::abs(x - 0.5) > 0.25 ? -64.0 : 64.0; }, 0.0, 1.0}};
}

// x equals the active-set solution to ~1e-8 relative; θ is the multiplier:
// H x + θ = b to round-off (E = I), θ ≥ 0 on the upper set, ≤ 0 on the lower,
// ≈ 0 where free, and it agrees with the active-set multiplier b − H x.
TEST(PenaltyDuality, MatchesActiveSetOnObstacleProblems) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const SparseMatrix H = laplacian_1d(c.n);
    const int m = static_cast<int>(H.rows());
    const Vector b = cellwise_load(c.n, c.f);
    const Vector lo = Vector::Constant(m, c.lo), hi = Vector::Constant(m, c.hi);
    SparseBoxQpOperator op(H);
    Vector x_as;
    const BoxQpResult ras = solve_box_qp(op, b, lo, hi, x_as);
    ASSERT_TRUE(ras.converged);
    const Vector mu_as = b - H * x_as;

    // ω of the order of the diagonal (as the damage and contact solvers use).
    PenaltyDuality pd(H, identity(m), H.diagonal().mean());
    Vector x, theta;
    const PenaltyDualityResult r = pd.solve(b, lo, hi, x, theta, 1e-13, 200000);
    ASSERT_TRUE(r.converged) << r.iterations << " iterations";
    ASSERT_EQ(theta.size(), m);
    const double xs = x_as.cwiseAbs().maxCoeff(), ms = mu_as.cwiseAbs().maxCoeff();
    EXPECT_LE((x - x_as).cwiseAbs().maxCoeff(), 1e-8 * xs);
    EXPECT_LE((theta - mu_as).cwiseAbs().maxCoeff(), 1e-7 * ms);
    // Equilibrium holds to round-off whatever the iteration count (θ is built for it).
    EXPECT_LE((H * x + theta - b).cwiseAbs().maxCoeff(), 1e-13 * b.cwiseAbs().maxCoeff());
    int n_signed = 0;
    for (int i = 0; i < m; ++i) {
      if (x_as[i] == c.hi) {
        EXPECT_GE(theta[i], 0.0) << i;
        ++n_signed;
      } else if (x_as[i] == c.lo) {
        EXPECT_LE(theta[i], 0.0) << i;
        ++n_signed;
      } else {
        EXPECT_LE(std::abs(theta[i]), 1e-8 * ms) << i;
      }
      // The constraint is met up to the stopping tolerance.
      EXPECT_GE(x[i], c.lo - 1e-10);
      EXPECT_LE(x[i], c.hi + 1e-10);
    }
    EXPECT_GT(n_signed, 0);
  }
}

// A general E (not the identity, fewer rows than unknowns, not unit rows): bounds
// on the differences of neighbours a_k = x_{k+1} − x_k ≥ −s, so E has entries ±1.
// Its fixed point must satisfy the KKT conditions of the original problem.
TEST(PenaltyDuality, GeneralConstraintMatrixSatisfiesKkt) {
  const int n = 30;
  const SparseMatrix H = laplacian_1d(n);
  const int m = static_cast<int>(H.rows());
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k + 1 < m; ++k) {
    t.emplace_back(k, k + 1, 1.0);
    t.emplace_back(k, k, -1.0);
  }
  SparseMatrix E(m - 1, m);
  E.setFromTriplets(t.begin(), t.end());
  const Vector b = cellwise_load(n, [](double) { return 8.0; });  // u = 4x(1 − x) unconstrained
  const double s = 0.05;
  const Vector lo = Vector::Constant(m - 1, -s), hi = Vector::Constant(m - 1, s);  // |slope·h| ≤ s
  PenaltyDuality pd(H, E, 2.0 * n);
  Vector x, theta;
  const PenaltyDualityResult r = pd.solve(b, lo, hi, x, theta, 1e-13, 200000);
  ASSERT_TRUE(r.converged) << r.iterations;
  EXPECT_LE((H * x + E.transpose() * theta - b).cwiseAbs().maxCoeff(), 1e-12 * b.cwiseAbs().maxCoeff());
  const Vector y = E * x;
  const double ts = theta.cwiseAbs().maxCoeff();
  int n_active = 0;
  for (int i = 0; i < m - 1; ++i) {
    EXPECT_GE(y[i], -s - 1e-10);
    EXPECT_LE(y[i], s + 1e-10);
    if (std::abs(y[i] - s) < 1e-9) {
      EXPECT_GE(theta[i], -1e-9 * ts);
      ++n_active;
    } else if (std::abs(y[i] + s) < 1e-9) {
      EXPECT_LE(theta[i], 1e-9 * ts);
      ++n_active;
    } else {
      EXPECT_LE(std::abs(theta[i]), 1e-9 * ts) << i;
    }
  }
  // The unconstrained slope 4(1 − 2x)·h reaches 4/30 > 0.05 near both ends only.
  EXPECT_GT(n_active, 0);
  EXPECT_LT(n_active, m - 1);
}

// The multiplier state is kept between calls: solving the same problem again
// reproduces the accepted iterate, so it stops after the first iteration.
TEST(PenaltyDuality, WarmStartReusesMultiplierState) {
  const Case c = cases()[2];
  const SparseMatrix H = laplacian_1d(c.n);
  const int m = static_cast<int>(H.rows());
  const Vector b = cellwise_load(c.n, c.f);
  const Vector lo = Vector::Constant(m, c.lo), hi = Vector::Constant(m, c.hi);
  PenaltyDuality pd(H, identity(m), H.diagonal().mean());
  Vector x, theta;
  const PenaltyDualityResult cold = pd.solve(b, lo, hi, x, theta, 1e-13, 200000);
  ASSERT_TRUE(cold.converged);
  EXPECT_GT(cold.iterations, 10);
  const Vector x0 = x;
  const PenaltyDualityResult warm = pd.solve(b, lo, hi, x, theta, 1e-13, 200000);
  EXPECT_TRUE(warm.converged);
  EXPECT_EQ(warm.iterations, 1);
  EXPECT_LE((x - x0).cwiseAbs().maxCoeff(), 1e-12);
}

// Hitting max_iterations reports converged = false and iterations = max_iterations.
TEST(PenaltyDuality, IterationLimitReportsNotConverged) {
  const Case c = cases()[2];
  const SparseMatrix H = laplacian_1d(c.n);
  const int m = static_cast<int>(H.rows());
  const Vector b = cellwise_load(c.n, c.f);
  PenaltyDuality pd(H, identity(m), H.diagonal().mean());
  Vector x, theta;
  const PenaltyDualityResult r =
      pd.solve(b, Vector::Constant(m, c.lo), Vector::Constant(m, c.hi), x, theta, 1e-13, 5);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, 5);
  EXPECT_EQ(x.size(), m);
  EXPECT_LE((H * x + theta - b).cwiseAbs().maxCoeff(), 1e-13 * b.cwiseAbs().maxCoeff());
}

// ω must be positive (vpc::Error naming omega), and H + ωEᵀE must be factorizable.
TEST(PenaltyDuality, InvalidOmegaThrows) {
  const SparseMatrix H = laplacian_1d(8);
  const int m = static_cast<int>(H.rows());
  for (double w : {0.0, -1.0}) {
    try {
      PenaltyDuality pd(H, identity(m), w);
      FAIL() << "expected vpc::Error for omega = " << w;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("omega"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace vpc
