// Box-constrained QP (primal–dual active set, solvers/box_qp): 1D obstacle problems
// whose discrete solution is known exactly, random dense problems against
// brute-force references, warm starts, degenerate bounds and the error path.
#include "solvers/box_qp.hpp"

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "mesh/generators.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <vector>

namespace vpc {
namespace {

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

/// Rows/cols 1..n-1 of an (n+1)×(n+1) matrix: the interior (Dirichlet) block.
SparseMatrix interior_block(const SparseMatrix& B, int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < B.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(B, k); it; ++it)
      if (it.row() > 0 && it.row() < n && it.col() > 0 && it.col() < n)
        t.emplace_back(static_cast<int>(it.row()) - 1, static_cast<int>(it.col()) - 1, it.value());
  SparseMatrix S(n - 1, n - 1);
  S.setFromTriplets(t.begin(), t.end());
  return S;
}

/// −u'' = f on (0, 1), u(0) = u(1) = 0, P1 on n cells: stiffness A, mass M of the
/// interior nodes x_i = i/n, i = 1..n-1, and the full mass matrix for loads.
struct Dirichlet1d {
  int n;
  double h;
  SparseMatrix A, M_full;
  double x(int k) const { return (k + 1) * h; }  // coordinate of interior unknown k
};

Dirichlet1d dirichlet_1d(int n) {
  const Mesh m = make_interval(0, 1, n);
  const auto geo = compute_geometry(m);
  Dirichlet1d p{n, 1.0 / n, interior_block(assemble_laplacian(m, geo), n), assemble_mass(m, geo)};
  return p;
}

/// Load (f, ψ_i) of interior nodes through the consistent mass matrix (f nodal).
Vector mass_load(const Dirichlet1d& p, const std::function<double(double)>& f) {
  Vector fn(p.n + 1);
  for (int i = 0; i <= p.n; ++i) fn[i] = f(static_cast<double>(i) / p.n);
  const Vector full = p.M_full * fn;
  return full.segment(1, p.n - 1);
}

/// Exact load ∫ f ψ_i for f constant on each cell (evaluated at cell midpoints).
Vector cellwise_load(const Dirichlet1d& p, const std::function<double(double)>& f) {
  Vector b(p.n - 1);
  for (int k = 0; k < p.n - 1; ++k) b[k] = 0.5 * p.h * (f(p.x(k) - 0.5 * p.h) + f(p.x(k) + 0.5 * p.h));
  return b;
}

/// Checks KKT directly (not through box_qp_kkt_residual): x in the box exactly,
/// μ = b − Hx ≈ 0 where free, μ ≤ 0 at the lower bound, μ ≥ 0 at the upper.
void expect_kkt(const Vector& Hx, const Vector& b, const Vector& lo, const Vector& hi, const Vector& x,
                double tol) {
  const Vector mu = b - Hx;
  const double scale = std::max(b.cwiseAbs().maxCoeff(), Hx.cwiseAbs().maxCoeff());
  for (int i = 0; i < x.size(); ++i) {
    ASSERT_GE(x[i], lo[i]) << i;
    ASSERT_LE(x[i], hi[i]) << i;
    if (x[i] == lo[i] && x[i] == hi[i]) continue;
    if (x[i] == lo[i])
      EXPECT_LE(mu[i], tol * scale) << "lower-bound multiplier of the wrong sign at " << i;
    else if (x[i] == hi[i])
      EXPECT_GE(mu[i], -tol * scale) << "upper-bound multiplier of the wrong sign at " << i;
    else
      EXPECT_LE(std::abs(mu[i]), tol * scale) << "gradient not zero at free index " << i;
  }
}

// Obstacle problem −u'' = −8, u ≥ −1/4: the exact solution touches the obstacle on
// [1/4, 3/4] (C¹ fit: u = 4(x − 1/4)² − 1/4 left of it). In 1D with a load exact
// for constant f, the P1 solution is nodally exact once the discrete contact set is
// {1/4 ≤ x ≤ 3/4} — so with 1/4 a node we can check to round-off, multipliers too.
double obstacle_exact(double x) {
  if (x < 0.25) return 4 * (x - 0.25) * (x - 0.25) - 0.25;
  if (x > 0.75) return 4 * (x - 0.75) * (x - 0.75) - 0.25;
  return -0.25;
}

TEST(BoxQp, LowerObstacleIsNodallyExact) {
  const Dirichlet1d p = dirichlet_1d(40);
  const int m = p.n - 1;
  const Vector b = mass_load(p, [](double) { return -8.0; });
  const Vector lo = Vector::Constant(m, -0.25), hi = Vector::Constant(m, kUnbounded);
  SparseBoxQpOperator H(p.A);
  Vector u;
  const BoxQpResult r = solve_box_qp(H, b, lo, hi, u);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.kkt_residual, 1e-12);
  EXPECT_LE(box_qp_kkt_residual(H, b, lo, hi, u), 1e-12);
  EXPECT_EQ(r.n_lower, 21);  // x = 10/40 .. 30/40
  EXPECT_EQ(r.n_upper, 0);
  expect_kkt(p.A * u, b, lo, hi, u, 1e-12);
  const Vector mu = p.A * u - b;  // the contact force (lower-bound multiplier)
  for (int k = 0; k < m; ++k) {
    EXPECT_NEAR(u[k], obstacle_exact(p.x(k)), 1e-13) << "x = " << p.x(k);
    const bool contact = k + 1 >= 10 && k + 1 <= 30;
    EXPECT_EQ(u[k] == -0.25, contact) << "x = " << p.x(k);  // bound attained exactly
    // μ = 8h inside the contact set, 4h at its two end nodes, 0 off it.
    const double mu_exact = !contact ? 0.0 : (k + 1 == 10 || k + 1 == 30 ? 4 * p.h : 8 * p.h);
    EXPECT_NEAR(mu[k], mu_exact, 1e-12) << "x = " << p.x(k);
  }
}

// Same problem with the free boundary x = 1/4 between nodes: no longer nodally
// exact, but the nodal error must be O(h²) (and the discrete KKT still exact).
TEST(BoxQp, LowerObstacleConvergesAtSecondOrder) {
  for (int n : {30, 90}) {
    const Dirichlet1d p = dirichlet_1d(n);
    const int m = p.n - 1;
    const Vector b = mass_load(p, [](double) { return -8.0; });
    const Vector lo = Vector::Constant(m, -0.25), hi = Vector::Constant(m, kUnbounded);
    SparseBoxQpOperator H(p.A);
    Vector u;
    const BoxQpResult r = solve_box_qp(H, b, lo, hi, u);
    ASSERT_TRUE(r.converged);
    EXPECT_LE(r.kkt_residual, 1e-12);
    expect_kkt(p.A * u, b, lo, hi, u, 1e-12);
    double err = 0;
    for (int k = 0; k < m; ++k) err = std::max(err, std::abs(u[k] - obstacle_exact(p.x(k))));
    EXPECT_LE(err, 1.5 * p.h * p.h) << "n = " << n;  // observed ≈ 0.9 h²
    EXPECT_GT(r.n_lower, 0);
  }
}

// Mirror image through an upper bound with lo = −∞: f = +8, u ≤ 1/4, u = −(above).
TEST(BoxQp, UpperObstacleIsNodallyExact) {
  const Dirichlet1d p = dirichlet_1d(40);
  const int m = p.n - 1;
  const Vector b = mass_load(p, [](double) { return 8.0; });
  const Vector lo = Vector::Constant(m, -kUnbounded), hi = Vector::Constant(m, 0.25);
  SparseBoxQpOperator H(p.A);
  Vector u = Vector::Zero(m);
  const BoxQpResult r = solve_box_qp(H, b, lo, hi, u);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.kkt_residual, 1e-12);
  EXPECT_EQ(r.n_upper, 21);
  EXPECT_EQ(r.n_lower, 0);
  expect_kkt(p.A * u, b, lo, hi, u, 1e-12);
  for (int k = 0; k < m; ++k) EXPECT_NEAR(u[k], -obstacle_exact(p.x(k)), 1e-13) << "x = " << p.x(k);
}

// Both bounds of [0, 1] active, as in the damage problem: f = −64 for |x − 1/2| > 1/4,
// +64 otherwise. Exact: u = 0 on [0, 1/8], 32(x − 1/8)² on [1/8, 1/4],
// 1 − 32(3/8 − x)² on [1/4, 3/8], u = 1 on [3/8, 5/8], symmetric; both multipliers
// are 64 away from the free boundaries, so with 1/8 a node it is nodally exact.
double two_sided_exact(double x) {
  if (x > 0.5) x = 1 - x;
  if (x <= 0.125) return 0;
  if (x <= 0.25) return 32 * (x - 0.125) * (x - 0.125);
  if (x <= 0.375) return 1 - 32 * (0.375 - x) * (0.375 - x);
  return 1;
}

TEST(BoxQp, TwoSidedBoxIsNodallyExact) {
  const Dirichlet1d p = dirichlet_1d(64);
  const int m = p.n - 1;
  const Vector b = cellwise_load(p, [](double x) { return std::abs(x - 0.5) > 0.25 ? -64.0 : 64.0; });
  const Vector lo = Vector::Zero(m), hi = Vector::Ones(m);
  SparseBoxQpOperator H(p.A);
  Vector u;
  const BoxQpResult r = solve_box_qp(H, b, lo, hi, u);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.kkt_residual, 1e-12);
  EXPECT_EQ(r.n_lower, 2 * 8);   // x = 1/64 .. 8/64 and its mirror
  EXPECT_EQ(r.n_upper, 17);      // x = 24/64 .. 40/64
  expect_kkt(p.A * u, b, lo, hi, u, 1e-12);
  const Vector mu = b - p.A * u;
  for (int k = 0; k < m; ++k) {
    EXPECT_NEAR(u[k], two_sided_exact(p.x(k)), 1e-13) << "x = " << p.x(k);
    const int i = std::min(k + 1, p.n - k - 1);  // node index, folded to the left half
    if (i == 8) {
      EXPECT_NEAR(mu[k], -32 * p.h, 1e-12);  // end of the β = 0 set
    }
    if (i == 24) {
      EXPECT_NEAR(mu[k], 32 * p.h, 1e-12);  // end of the β = 1 set
    }
  }
}

// ---------------------------------------------------------------- random dense QPs

struct RandomQp {
  Eigen::MatrixXd H;
  Vector b, lo, hi;
};

/// SPD H = BᵀB/n + 0.1 I (full, not an M-matrix, condition ≲ 50); bounds with some
/// infinite ones (and some equal ones) and b large enough that many bounds are active.
RandomQp random_qp(int n, std::mt19937& rng) {
  std::normal_distribution<double> N01;
  std::uniform_real_distribution<double> U(0, 1);
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = N01(rng);
  RandomQp q;
  q.H = B.transpose() * B / n + 0.1 * Eigen::MatrixXd::Identity(n, n);
  q.H = 0.5 * (q.H + q.H.transpose()).eval();
  q.b.resize(n);
  q.lo.resize(n);
  q.hi.resize(n);
  for (int i = 0; i < n; ++i) {
    q.b[i] = 2 * N01(rng);
    const double a = U(rng);
    q.lo[i] = a < 0.2 ? -kUnbounded : -U(rng);
    const double c = U(rng);
    q.hi[i] = c < 0.2 ? kUnbounded : (c < 0.25 && std::isfinite(q.lo[i]) ? q.lo[i] : U(rng));
  }
  return q;
}

double objective(const RandomQp& q, const Vector& x) { return 0.5 * x.dot(q.H * x) - q.b.dot(x); }

/// Brute force: every assignment free / lower / upper, the free part solved exactly;
/// the feasible candidate of least objective is the (unique) minimizer.
Vector enumerate_reference(const RandomQp& q) {
  const int n = static_cast<int>(q.b.size());
  int total = 1;
  for (int i = 0; i < n; ++i) total *= 3;
  Vector best;
  double best_f = kUnbounded;
  for (int code = 0; code < total; ++code) {
    Vector x = Vector::Zero(n);
    std::vector<int> F;
    bool ok = true;
    for (int i = 0, c = code; i < n; ++i, c /= 3) {
      const int s = c % 3;
      if (s == 0) F.push_back(i);
      if (s == 1) x[i] = q.lo[i];
      if (s == 2) x[i] = q.hi[i];
      if (!std::isfinite(x[i])) ok = false;
    }
    if (!ok) continue;
    const int nf = static_cast<int>(F.size());
    if (nf > 0) {
      Eigen::MatrixXd HFF(nf, nf);
      Vector r(nf);
      const Vector Hx = q.H * x;
      for (int a = 0; a < nf; ++a) {
        r[a] = q.b[F[a]] - Hx[F[a]];
        for (int c = 0; c < nf; ++c) HFF(a, c) = q.H(F[a], F[c]);
      }
      const Vector xf = HFF.ldlt().solve(r);
      for (int a = 0; a < nf; ++a) x[F[a]] = xf[a];
    }
    for (int i = 0; i < n && ok; ++i) ok = x[i] >= q.lo[i] - 1e-12 && x[i] <= q.hi[i] + 1e-12;
    if (!ok) continue;
    const double f = objective(q, x);
    if (f < best_f) {
      best_f = f;
      best = x;
    }
  }
  return best;
}

/// Projected Gauss–Seidel (exact coordinate minimization), run to stagnation.
Vector pgs_reference(const RandomQp& q) {
  const int n = static_cast<int>(q.b.size());
  Vector x = Vector::Zero(n);
  for (int i = 0; i < n; ++i) x[i] = std::clamp(0.0, q.lo[i], q.hi[i]);
  for (int sweep = 0; sweep < 200000; ++sweep) {
    double change = 0;
    for (int i = 0; i < n; ++i) {
      const double xi = std::clamp(x[i] + (q.b[i] - q.H.col(i).dot(x)) / q.H(i, i), q.lo[i], q.hi[i]);
      change = std::max(change, std::abs(xi - x[i]));
      x[i] = xi;
    }
    if (change <= 1e-15 * std::max(1.0, x.cwiseAbs().maxCoeff())) break;
  }
  return x;
}

// Small random problems against enumeration of all 3ⁿ active sets.
TEST(BoxQp, DenseRandomMatchesEnumeration) {
  std::mt19937 rng(20030101);
  int n_active_total = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 2 + trial % 7;  // 2..8
    const RandomQp q = random_qp(n, rng);
    const Vector ref = enumerate_reference(q);
    ASSERT_EQ(ref.size(), n);
    DenseBoxQpOperator H(q.H);
    Vector x;
    const BoxQpResult r = solve_box_qp(H, q.b, q.lo, q.hi, x);
    ASSERT_TRUE(r.converged) << "trial " << trial;
    EXPECT_LE(r.kkt_residual, 1e-13) << "trial " << trial;
    EXPECT_LE((x - ref).cwiseAbs().maxCoeff(), 1e-10 * std::max(1.0, ref.cwiseAbs().maxCoeff()))
        << "trial " << trial;
    expect_kkt(q.H * x, q.b, q.lo, q.hi, x, 1e-12);
    n_active_total += r.n_lower + r.n_upper;
  }
  EXPECT_GT(n_active_total, 60);  // the generator does exercise the bounds
}

// Larger random problems (n = 5..50) against projected Gauss–Seidel.
TEST(BoxQp, DenseRandomMatchesProjectedGaussSeidel) {
  std::mt19937 rng(4242);
  for (int trial = 0; trial < 24; ++trial) {
    const int n = 5 + (trial * 45) / 23;  // 5..50
    const RandomQp q = random_qp(n, rng);
    const Vector ref = pgs_reference(q);
    DenseBoxQpOperator H(q.H);
    Vector x;
    const BoxQpResult r = solve_box_qp(H, q.b, q.lo, q.hi, x);
    ASSERT_TRUE(r.converged) << "trial " << trial << ", n = " << n;
    EXPECT_LT(r.iterations, 50);
    EXPECT_LE(r.kkt_residual, 1e-13);
    expect_kkt(q.H * x, q.b, q.lo, q.hi, x, 1e-12);
    EXPECT_LE((x - ref).cwiseAbs().maxCoeff(), 1e-10 * std::max(1.0, ref.cwiseAbs().maxCoeff()))
        << "trial " << trial << ", n = " << n;
    EXPECT_LE(objective(q, x), objective(q, ref) + 1e-13 * std::abs(objective(q, ref)));
  }
}

// ---------------------------------------------------------------- warm start, limits

// BoxQpResult::iterations counts the reduced solves, and the method stops as soon as
// x satisfies KKT to round-off: restarting from a solution must do no solve at all
// (iterations = 0, x unchanged). With slightly perturbed data and the same active
// set it must take exactly one solve — the set then repeats — and, for the sparse
// operator, reuse the cached reduced factor (no new factorization).
TEST(BoxQp, WarmStartFromSolutionStopsAtOnce) {
  const Dirichlet1d p = dirichlet_1d(64);
  const int m = p.n - 1;
  const Vector b = cellwise_load(p, [](double x) { return std::abs(x - 0.5) > 0.25 ? -64.0 : 64.0; });
  const Vector lo = Vector::Zero(m), hi = Vector::Ones(m);
  SparseBoxQpOperator H(p.A);
  Vector u;
  const BoxQpResult cold = solve_box_qp(H, b, lo, hi, u);
  ASSERT_TRUE(cold.converged);
  EXPECT_GT(cold.iterations, 1);
  const int nf = H.n_factorizations();
  const Vector u0 = u;
  const BoxQpResult warm = solve_box_qp(H, b, lo, hi, u);
  EXPECT_TRUE(warm.converged);
  EXPECT_EQ(warm.iterations, 0);
  EXPECT_EQ(u, u0);
  EXPECT_EQ(H.n_factorizations(), nf);
  EXPECT_EQ(warm.n_lower, cold.n_lower);
  EXPECT_EQ(warm.n_upper, cold.n_upper);

  const Vector b2 = b * (1 + 1e-8);  // same active set, different free values
  const BoxQpResult next = solve_box_qp(H, b2, lo, hi, u);
  EXPECT_TRUE(next.converged);
  EXPECT_EQ(next.iterations, 1);
  EXPECT_EQ(H.n_factorizations(), nf);  // the reduced factor of the same set is reused
  EXPECT_EQ(next.n_lower, cold.n_lower);
  EXPECT_EQ(next.n_upper, cold.n_upper);
  EXPECT_GT((u - u0).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LE(next.kkt_residual, 1e-13);

  std::mt19937 rng(7);
  const RandomQp q = random_qp(30, rng);
  DenseBoxQpOperator D(q.H);
  Vector x;
  ASSERT_TRUE(solve_box_qp(D, q.b, q.lo, q.hi, x).converged);
  const Vector x0 = x;
  const BoxQpResult again = solve_box_qp(D, q.b, q.lo, q.hi, x);
  EXPECT_TRUE(again.converged);
  EXPECT_EQ(again.iterations, 0);
  EXPECT_EQ(x, x0);
}

// max_iterations is a hard limit: a cold start that needs several solves, given one,
// returns converged = false with iterations = 1 — and still x exactly in the box.
TEST(BoxQp, IterationLimitReportsNotConverged) {
  const Dirichlet1d p = dirichlet_1d(64);
  const int m = p.n - 1;
  const Vector b = cellwise_load(p, [](double x) { return std::abs(x - 0.5) > 0.25 ? -64.0 : 64.0; });
  const Vector lo = Vector::Zero(m), hi = Vector::Ones(m);
  SparseBoxQpOperator H(p.A);
  Vector u;
  const BoxQpResult r = solve_box_qp(H, b, lo, hi, u, 1);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_GT(r.kkt_residual, 1e-6);
  EXPECT_GE(u.minCoeff(), 0.0);
  EXPECT_LE(u.maxCoeff(), 1.0);
}

// Degenerate bounds: the unconstrained minimizer x* lies exactly on a bound at many
// indices (multiplier exactly 0), with b = Hx* rounded so that b − Hx* is ±round-off.
// The sign of that round-off decides free/active, and it used to flip forever (with
// the KKT stopping test removed this test does fail); the method must stop, with KKT
// satisfied to round-off, at x*, from any start.
TEST(BoxQp, DegenerateBoundsConverge) {
  const Dirichlet1d p = dirichlet_1d(200);
  const int m = p.n - 1;
  Vector xs(m), lo(m), hi(m);
  for (int k = 0; k < m; ++k) {
    const double v = 0.1 * std::sin(7.3 * p.x(k)) + 0.3;  // in (0.2, 0.4)
    lo[k] = k % 3 == 0 ? v : 0.0;        // x* on its lower bound
    hi[k] = k % 3 == 1 ? v : kUnbounded;       // x* on its upper bound
    xs[k] = v;
  }
  const Vector b = p.A * xs;
  for (int start = 0; start < 3; ++start) {
    SparseBoxQpOperator H(p.A);
    Vector u = start == 0 ? Vector() : (start == 1 ? Vector(Vector::Ones(m)) : Vector(xs));
    const BoxQpResult r = solve_box_qp(H, b, lo, hi, u, 50);
    EXPECT_TRUE(r.converged) << "start " << start << ": " << r.iterations << " iterations";
    EXPECT_LE(r.kkt_residual, 1e-13);
    EXPECT_LE((u - xs).cwiseAbs().maxCoeff(), 1e-12) << "start " << start;
  }
  // The same on a dense operator (the contact path).
  const int n = 12;
  Eigen::MatrixXd Hd = Eigen::MatrixXd(p.A).topLeftCorner(n, n);
  const Vector xd = xs.head(n), bd = Hd * xd, lod = lo.head(n), hid = hi.head(n);
  DenseBoxQpOperator D(Hd);
  Vector x;
  const BoxQpResult r = solve_box_qp(D, bd, lod, hid, x, 50);
  EXPECT_TRUE(r.converged) << r.iterations << " iterations";
  EXPECT_LE((x - xd).cwiseAbs().maxCoeff(), 1e-12);
}

/// A 2D damage-like matrix H = M + kκA on a 12 × 12 grid (169 unknowns).
SparseMatrix damage_matrix_2d() {
  const Mesh mesh = make_rectangle({0, 0, 0}, {1, 1, 0}, 12, 12);
  const auto geo = compute_geometry(mesh);
  return assemble_mass(mesh, geo) + 0.01 * assemble_laplacian(mesh, geo);
}

// An index with lo = hi is no unknown: it is held from the first iteration, whatever the sign
// of its multiplier, never released by the monotone updates, and x there is its value exactly;
// the rest is the reduced solve's. Where its value also solves the unconstrained problem (a
// degenerate bound, the undamaged foundation's β = 1) round-off must not make it flip.
TEST(BoxQp, EqualBoundsAreHeldFromTheFirstIteration) {
  const SparseMatrix H = damage_matrix_2d();
  const int n = static_cast<int>(H.rows());
  Vector lo = Vector::Constant(n, -kUnbounded), hi = Vector::Constant(n, kUnbounded), xs(n);
  for (int i = 0; i < n; ++i) xs[i] = 0.5 + 0.3 * std::sin(0.37 * i);
  const Vector b = H * xs;
  std::vector<char> fixed(n, 0);
  for (int i = 0; i < n; i += 5) {  // held above, below and at x*
    fixed[i] = 1;
    lo[i] = hi[i] = xs[i] + (i % 15 == 0 ? 0.2 : i % 15 == 5 ? -0.2 : 0.0);
  }
  Vector ref = xs;
  for (int i = 0; i < n; ++i)
    if (fixed[i]) ref[i] = lo[i];
  SparseBoxQpOperator direct(H);
  direct.solve_free(fixed, b, ref);
  for (const Vector& start : {Vector(Vector::Zero(n)), xs}) {
    SparseBoxQpOperator op(H);
    Vector x = start;
    const BoxQpResult r = solve_box_qp(op, b, lo, hi, x, 50);
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.iterations, 1);  // one reduced solve; then the sets repeat
    EXPECT_EQ(r.cycles, 0);
    EXPECT_LE(r.kkt_residual, 1e-14);
    for (int i = 0; i < n; ++i) {
      if (fixed[i]) {
        ASSERT_EQ(x[i], lo[i]) << i;
      }
    }
    EXPECT_LE((x - ref).cwiseAbs().maxCoeff(), 1e-13);
  }
}

// Reduced systems H_FF x_F = b_F − H_FA x_A by the capacitance method (the factor
// of the whole H only) and by a factor of H_FF agree, for growing, shrinking and
// repeated active sets; x_A keeps its given values exactly.
TEST(BoxQp, CapacitanceAndReducedFactorSolveTheSameSystems) {
  const SparseMatrix Hs = damage_matrix_2d();
  const int n = static_cast<int>(Hs.rows());
  SparseBoxQpOperator cap(Hs, ReducedSolve::capacitance), fac(Hs, ReducedSolve::reduced_factor);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  const Vector b = Vector::Random(n);
  for (int sizes : {3, 10, 40, 10, 10, 90}) {
    std::vector<char> fixed(n, 0);
    Vector x0 = Vector::Zero(n);
    for (int k = 0; k < sizes; ++k) {
      const int i = static_cast<int>(U(rng) * n) % n;
      fixed[i] = 1;
      x0[i] = U(rng);
    }
    Vector x1 = x0, x2 = x0;
    cap.solve_free(fixed, b, x1);
    fac.solve_free(fixed, b, x2);
    EXPECT_LE((x1 - x2).cwiseAbs().maxCoeff(), 1e-11 * x2.cwiseAbs().maxCoeff()) << sizes << " fixed";
    const Vector r = b - Hs * x1;
    for (int i = 0; i < n; ++i) {
      if (fixed[i]) EXPECT_EQ(x1[i], x0[i]);
      else EXPECT_NEAR(r[i], 0.0, 1e-12 * b.cwiseAbs().maxCoeff());
    }
  }
  EXPECT_EQ(cap.n_capacitance_solves(), 6);
  EXPECT_EQ(fac.n_reduced_factor_solves(), 6);
  EXPECT_EQ(cap.n_factorizations(), 1);  // only the whole H, ever
}

// Automatic choice: a few active bounds go by capacitance, nearly all of them by a
// reduced factor (whose cost shrinks with the free set while the capacitance's grows).
TEST(BoxQp, AutomaticReducedSolveChoosesByCost) {
  const SparseMatrix Hs = damage_matrix_2d();
  const int n = static_cast<int>(Hs.rows());
  SparseBoxQpOperator H(Hs);
  H.set_costs(1e-3, 1e-4);  // not the measured times: the test must not depend on the machine
  const Vector b = Vector::Random(n);
  std::vector<char> few(n, 0), most(n, 1);
  few[n / 2] = 1;
  most[n / 2] = 0;
  Vector x = Vector::Zero(n);
  H.solve_free(few, b, x);
  EXPECT_EQ(H.n_capacitance_solves(), 1);
  x = Vector::Zero(n);
  H.solve_free(most, b, x);
  EXPECT_EQ(H.n_reduced_factor_solves(), 1);
  EXPECT_NEAR(x[n / 2], (b[n / 2]) / Hs.coeff(n / 2, n / 2), 1e-14);
}

// Infeasible box: lo > hi is a user error (vpc::Error naming the index), not UB.
TEST(BoxQp, CrossedBoundsThrow) {
  DenseBoxQpOperator H(Eigen::MatrixXd::Identity(3, 3));
  const Vector b = Vector::Zero(3), lo = Vector::Constant(3, 0.0);
  Vector hi = Vector::Ones(3);
  hi[2] = -1;
  Vector x;
  try {
    solve_box_qp(H, b, lo, hi, x);
    FAIL() << "expected vpc::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("index 2"), std::string::npos) << e.what();
  }
}

// A dense H that is not an M-matrix, on which the plain primal–dual active-set update
// cycles from x = 0 ({0, 2}, {}, {1, 2}, {0, 2} again): the guard switches to monotone
// updates and ends at the one KKT point, x = (1.52395117, 2.18511895, 0) with index 2 at
// its bound (found by enumerating the 8 sets).
TEST(BoxQp, ACyclingActiveSetIsEndedByMonotoneUpdates) {
  Eigen::MatrixXd K(3, 3);
  K << 6.617, -2.169, -4.035, -2.169, 3.049, 2.483, -4.035, 2.483, 3.298;
  const Eigen::MatrixXd H = K.inverse();
  const Vector b = H * (Vector(3) << 5.265, 0.379, -2.792).finished() - (Vector(3) << 0.103, 0.175, 0.073).finished();
  DenseBoxQpOperator op(H);
  Vector x;
  const BoxQpResult r = solve_box_qp(op, b, Vector::Zero(3), Vector::Constant(3, kUnbounded), x);
  ASSERT_TRUE(r.converged) << r.iterations << " iterations";
  EXPECT_EQ(r.cycles, 1);
  EXPECT_LE(r.kkt_residual, 1e-14);
  EXPECT_NEAR(x[0], 1.52395117, 1e-8);
  EXPECT_NEAR(x[1], 2.18511895, 1e-8);
  EXPECT_EQ(x[2], 0.0);
  EXPECT_EQ(r.n_lower, 1);
}

}  // namespace
}  // namespace vpc
